#include "crowd/runtime/impostor_runtime.h"

#include <algorithm>
#include <cmath>

#include "crowd/formats/bc5.h"

namespace crowd::runtime {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

ImpostorChoice chooseImpostorView(const pack::Impostor &m, glm::vec3 toEye, double clipTime,
                                  bool loop) {
  ImpostorChoice c;
  double f = m.frameStep > 0 ? clipTime / double(m.frameStep) : 0.0;
  if (loop)
    f -= double(m.frames) * std::floor(f / double(m.frames));
  // The nearest sampled frame; past the last one a loop shows frame 0 again.
  long frame = std::lround(std::clamp(f, 0.0, double(loop ? m.frames : m.frames - 1)));
  c.frame = uint32_t(frame) % m.frames;
  double az = std::atan2(double(toEye.x), double(toEye.z));
  long a = std::lround(az / (2 * kPi / m.azimuths));
  c.azimuth = uint32_t(((a % long(m.azimuths)) + long(m.azimuths)) % long(m.azimuths));
  double len = glm::length(glm::dvec3(toEye));
  double el = len > 0 ? std::asin(std::clamp(double(toEye.y) / len, 0.0, 1.0)) : 0.0;
  c.elevation =
      uint32_t(std::min(std::floor(el / (0.5 * kPi / m.elevations)), double(m.elevations - 1)));
  auto [view, flip] = m.lookup(c.frame, c.elevation, c.azimuth);
  c.view = view;
  c.flip = flip;
  c.frame = uint32_t(view / (size_t(m.elevations) * m.storedAzimuths()));
  return c;
}

double oneToOneDistance(const pack::Impostor &m, double fovY, int viewportHeight) {
  double texel = 2.0 * double(m.sphere[3]) / double(m.texels);
  return texel * double(viewportHeight) / (2.0 * std::tan(fovY / 2));
}

uint32_t impostorMipLevels(const pack::Impostor &m) {
  uint32_t smallest = UINT32_MAX;
  for (const auto &v : m.views)
    if (v.width && v.height)
      smallest = std::min<uint32_t>(smallest, std::min(v.width, v.height));
  uint32_t levels = 1;
  while (levels < 6 && (smallest >> levels) >= 2)
    ++levels;
  return levels;
}

std::vector<ImpostorMip> impostorMips(const pack::Impostor &m, uint32_t frame, uint32_t levels) {
  const size_t texels = m.frameTexels(), blocks = pack::bc5Bytes(m.atlasWidth, m.atlasHeight);
  std::vector<ImpostorMip> mips(1);
  ImpostorMip &base = mips[0]; // the stored blocks as they are
  base.width = m.atlasWidth;
  base.height = m.atlasHeight;
  base.normals.assign(m.normals.begin() + long(frame * blocks),
                      m.normals.begin() + long((frame + 1) * blocks));
  base.regions.assign(m.regions.begin() + long(frame * texels),
                      m.regions.begin() + long((frame + 1) * texels));
  if (!m.uvs.empty())
    base.uvs.assign(m.uvs.begin() + long(frame * blocks),
                    m.uvs.begin() + long((frame + 1) * blocks));
  // The level above as decoded values (octahedral normal, UV), each level picked from them.
  const pack::ImpostorTexels decoded = pack::decodeTexels(m, frame);
  std::vector<float> oct = decoded.oct, uv = decoded.uv;
  while (mips.size() < levels && (mips.back().width > 1 || mips.back().height > 1)) {
    const ImpostorMip &src = mips.back();
    ImpostorMip dst;
    dst.width = std::max(1u, src.width / 2);
    dst.height = std::max(1u, src.height / 2);
    dst.regions.assign(size_t(dst.width) * dst.height, 0);
    std::vector<float> dstOct(dst.regions.size() * 2, 0.5f), dstUv(uv.empty() ? 0 : dstOct.size());
    for (uint32_t y = 0; y < dst.height; ++y)
      for (uint32_t x = 0; x < dst.width; ++x) {
        size_t block[4];
        int n = 0, inside = 0;
        for (uint32_t sy = 2 * y; sy < std::min(2 * y + 2, src.height); ++sy)
          for (uint32_t sx = 2 * x; sx < std::min(2 * x + 2, src.width); ++sx) {
            size_t i = size_t(sy) * src.width + sx;
            ++inside;
            if (src.regions[i] != 0)
              block[n++] = i;
          }
        if (n == 0 || 2 * n < inside)
          continue;
        size_t pick = block[0];
        int bestCount = 0;
        for (int k = 0; k < n; ++k) {
          uint8_t region = src.regions[block[k]];
          int count = 0;
          for (int j = 0; j < n; ++j)
            count += src.regions[block[j]] == region;
          if (count > bestCount || (count == bestCount && region < src.regions[pick]))
            bestCount = count, pick = block[k];
        }
        size_t o = size_t(y) * dst.width + x;
        dst.regions[o] = src.regions[pick];
        std::copy_n(&oct[pick * 2], 2, &dstOct[o * 2]);
        if (!uv.empty())
          std::copy_n(&uv[pick * 2], 2, &dstUv[o * 2]);
      }
    dst.normals = pack::encodeBc5(dstOct.data(), dst.regions.data(), dst.width, dst.height);
    if (!uv.empty())
      dst.uvs = pack::encodeBc5(dstUv.data(), dst.regions.data(), dst.width, dst.height);
    oct = std::move(dstOct), uv = std::move(dstUv);
    mips.push_back(std::move(dst));
  }
  return mips;
}

} // namespace crowd::runtime
