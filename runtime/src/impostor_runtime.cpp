#include "crowd/runtime/impostor_runtime.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/gtc/type_ptr.hpp>

#include "crowd/formats/bc5.h"

namespace crowd::runtime {

ImpostorFrame impostorViewFrame(double azimuth, double elevation) {
  ImpostorFrame v;
  v.dir = {std::cos(elevation) * std::sin(azimuth), std::sin(elevation),
           std::cos(elevation) * std::cos(azimuth)};
  v.right = glm::normalize(glm::cross(-v.dir, glm::dvec3(0, 1, 0)));
  v.up = glm::cross(v.right, -v.dir);
  return v;
}

ImpostorFrame impostorViewFrame(const pack::Impostor &m, uint32_t elevation, uint32_t azimuth) {
  return impostorViewFrame(2 * std::numbers::pi * azimuth / m.azimuths,
                           0.5 * std::numbers::pi * (elevation + 0.5) / m.elevations);
}

ImpostorChoice chooseImpostorViews(const pack::Impostor &m, glm::dvec3 toEye, double clipTime,
                                   bool loop) {
  ImpostorChoice c;
  double f = m.frameStep > 0 ? clipTime / double(m.frameStep) : 0.0;
  if (loop)
    f -= double(m.frames) * std::floor(f / double(m.frames));
  // The nearest sampled frame; past the last one a loop shows frame 0 again.
  long frame = std::lround(std::clamp(f, 0.0, double(loop ? m.frames : m.frames - 1)));
  c.frame = uint32_t(frame) % m.frames;
  // Grid coordinates: azimuth a sits at a, elevation row e at e (rows at 90 (e + 0.5) / E
  // degrees; below the first and above the last row the nearest row).
  const double len = glm::length(toEye);
  const double el = len > 0 ? std::asin(std::clamp(toEye.y / len, 0.0, 1.0)) : 0.0;
  const double ga = std::atan2(toEye.x, toEye.z) / (2 * std::numbers::pi / m.azimuths);
  const double ge =
      std::clamp(el / (0.5 * std::numbers::pi / m.elevations) - 0.5, 0.0, double(m.elevations - 1));
  const long a0 = long(std::floor(ga)), e0 = std::min(long(ge), long(m.elevations) - 1);
  const long e1 = std::min(e0 + 1, long(m.elevations) - 1);
  const double s = ga - double(a0), t = ge - double(e0);
  struct Corner {
    long a, e;
    double w;
  };
  const Corner corners[3] = {s + t <= 1 ? Corner{a0, e0, 1 - s - t} : Corner{a0 + 1, e1, s + t - 1},
                             s + t <= 1 ? Corner{a0 + 1, e0, s} : Corner{a0 + 1, e0, 1 - t},
                             s + t <= 1 ? Corner{a0, e1, t} : Corner{a0, e1, 1 - s}};
  for (const Corner &k : corners) {
    if (!(k.w > 1e-9))
      continue;
    ImpostorViewWeight &v = c.views[c.count++];
    v.azimuth = uint32_t(((k.a % long(m.azimuths)) + long(m.azimuths)) % long(m.azimuths));
    v.elevation = uint32_t(k.e);
    v.weight = k.w;
    v.frame = impostorViewFrame(m, v.elevation, v.azimuth);
    auto [view, flip] = m.lookup(c.frame, v.elevation, v.azimuth);
    v.view = view;
    v.flip = flip;
    v.layer = uint32_t(view / (size_t(m.elevations) * m.storedAzimuths()));
  }
  std::stable_sort(c.views, c.views + c.count,
                   [](const auto &a, const auto &b) { return a.weight > b.weight; });
  return c;
}

ImpostorSample sampleImpostor(const pack::Impostor &m,
                              const std::vector<pack::ImpostorTexels> &layers,
                              const ImpostorChoice &choice, glm::dvec3 origin, glm::dvec3 ray) {
  const glm::dvec3 centre(m.sphere[0], m.sphere[1], m.sphere[2]);
  const double texel = 2.0 * double(m.sphere[3]) / double(m.texels);
  double cover = 0;
  glm::dvec3 normal(0);
  ImpostorSample out;
  bool found = false; // a view whose nearest texel is covered (the heaviest first)
  for (int k = 0; k < choice.count; ++k) {
    const ImpostorViewWeight &vw = choice.views[k];
    const pack::ImpostorView &view = m.views[vw.view];
    const pack::ImpostorTexels &atlas = layers[vw.layer];
    const ImpostorFrame &f = vw.frame;
    // The plane z = offset + slopeX x + slopeY y of the stored view (x mirrored when flipped).
    const double slopeX = vw.flip ? -double(view.slopeX) : double(view.slopeX);
    const glm::dvec3 n = f.dir - slopeX * f.right - double(view.slopeY) * f.up;
    const double along = glm::dot(ray, n);
    if (std::abs(along) < 1e-12)
      continue;
    const glm::dvec3 q =
        origin - centre + ray * ((double(view.planeOffset) - glm::dot(origin - centre, n)) / along);
    // Texels from the crop's corner.
    const double sx = glm::dot(q, f.right) / texel;
    const double cx = vw.flip ? double(view.pivotX) - sx : double(view.pivotX) + sx;
    const double cy = double(view.pivotY) - glm::dot(q, f.up) / texel;
    auto at = [&](long x, long y) -> long { // the atlas texel, or -1 outside the crop or empty
      if (x < 0 || y < 0 || x >= long(view.width) || y >= long(view.height))
        return -1;
      const long i = (long(view.y) + y) * long(m.atlasWidth) + long(view.x) + x;
      return atlas.regions[size_t(i)] ? i : -1;
    };
    const long bx = long(std::floor(cx - 0.5)), by = long(std::floor(cy - 0.5));
    const double fx = cx - 0.5 - double(bx), fy = cy - 0.5 - double(by);
    const double occupancy =
        (1 - fx) * (1 - fy) * (at(bx, by) >= 0) + fx * (1 - fy) * (at(bx + 1, by) >= 0) +
        (1 - fx) * fy * (at(bx, by + 1) >= 0) + fx * fy * (at(bx + 1, by + 1) >= 0);
    cover += vw.weight * occupancy;
    const long nearest = at(long(std::floor(cx)), long(std::floor(cy)));
    if (nearest < 0)
      continue;
    const auto d = atlas.normal(size_t(nearest));
    normal += vw.weight * glm::dvec3(vw.flip ? -d[0] : d[0], d[1], d[2]);
    if (!found) {
      found = true;
      out.region = atlas.regions[size_t(nearest)];
      if (!atlas.uv.empty())
        out.uv = {atlas.uv[size_t(nearest) * 2], atlas.uv[size_t(nearest) * 2 + 1]};
    }
  }
  out.covered = cover >= 0.5 && found;
  if (glm::length(normal) > 0)
    out.normal = glm::normalize(normal);
  return out;
}

double oneToOneDistance(const pack::Impostor &m, double fovY, int viewportHeight) {
  double texel = 2.0 * double(m.sphere[3]) / double(m.texels);
  return texel * double(viewportHeight) / (2.0 * std::tan(fovY / 2));
}

double diffuseTexelsPerUnit(const pack::Mesh &mesh, uint32_t width, uint32_t height) {
  if (mesh.uvs.size() != 2 * mesh.vertexCount())
    return 0;
  double surface = 0, texture = 0;
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const uint32_t *v = &mesh.indices[t];
    auto at = [&](int k) { return glm::dvec3(glm::make_vec3(&mesh.positions[3 * size_t(v[k])])); };
    auto uv = [&](int k) { return glm::dvec2(glm::make_vec2(&mesh.uvs[2 * size_t(v[k])])); };
    surface += glm::length(glm::cross(at(1) - at(0), at(2) - at(0)));
    const glm::dvec2 a = uv(1) - uv(0), b = uv(2) - uv(0);
    texture += std::abs(a.x * b.y - a.y * b.x) * double(width) * double(height);
  }
  return surface > 0 ? std::sqrt(texture / surface) : 0;
}

uint32_t impostorMipLevels(const pack::Impostor &m) {
  uint32_t smallest = UINT32_MAX;
  for (const auto &v : m.views)
    if (v.width && v.height)
      smallest = std::min<uint32_t>(smallest, std::min(v.width, v.height));
  uint32_t levels = 1;
  while (levels < kImpostorMaxMipLevels && (smallest >> levels) >= 2)
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
