#include "crowd/formats/impostor.h"

#include <algorithm>
#include <cmath>

#include "crowd/formats/bc5.h"
#include "crowd/formats/bytes.h"
#include "crowd/formats/error.h"
#include "crowd/formats/impostor_spans.h"
#include "crowd/formats/registry.h"

namespace crowd::pack {

uint64_t Impostor::bytesPerFrame() const {
  if (frames == 0)
    return 0;
  const size_t perFrame = views.size() / frames;
  uint64_t bytes = 0;
  for (uint32_t f = 0; f < frames; ++f) {
    const ImpostorSpans s = impostorSpans(
        std::span(views).subspan(f * perFrame, perFrame),
        std::span(regions).subspan(f * frameTexels(), frameTexels()), atlasWidth, atlasHeight, 0);
    const uint64_t planes = uvs.empty() ? 1 : 2;
    bytes += s.sourceBlocks.size() * kBc5BlockBytes * planes +
             (s.rows.size() + s.viewRows.size()) * 8; // the player's span buffer: 2 words each
  }
  return uint64_t(regionRowBytes(atlasWidth, regionBits())) * atlasHeight + bytes / frames;
}

uint32_t Impostor::regionBits() const {
  return regions.empty() || *std::max_element(regions.begin(), regions.end()) <= 15 ? 4 : 8;
}

std::array<float, 2> octEncode(const std::array<float, 3> &n) {
  float s = std::abs(n[0]) + std::abs(n[1]) + std::abs(n[2]);
  if (!(s > 0))
    return {0.5f, 0.5f};
  float x = n[0] / s, y = n[1] / s;
  if (n[2] < 0) { // the lower half folds over the diagonals
    float fx = (1 - std::abs(y)) * (x < 0 ? -1.0f : 1.0f);
    float fy = (1 - std::abs(x)) * (y < 0 ? -1.0f : 1.0f);
    x = fx, y = fy;
  }
  return {x * 0.5f + 0.5f, y * 0.5f + 0.5f};
}

std::array<float, 3> octDecode(float ox, float oy) {
  float x = ox * 2 - 1, y = oy * 2 - 1, z = 1 - std::abs(x) - std::abs(y);
  if (z < 0) {
    float fx = (1 - std::abs(y)) * (x < 0 ? -1.0f : 1.0f);
    float fy = (1 - std::abs(x)) * (y < 0 ? -1.0f : 1.0f);
    x = fx, y = fy;
  }
  float len = std::sqrt(x * x + y * y + z * z);
  return {x / len, y / len, z / len};
}

namespace {

// Per block of every frame (frame-major, rows of blocks): whether any of its texels is covered.
std::vector<uint8_t> usedBlocks(const Impostor &m) {
  const uint32_t bw = (m.atlasWidth + 3) / 4, bh = (m.atlasHeight + 3) / 4;
  std::vector<uint8_t> used(size_t(m.frames) * bw * bh, 0);
  for (size_t t = 0; t < m.regions.size(); ++t)
    if (m.regions[t]) {
      const size_t f = t / m.frameTexels(), i = t % m.frameTexels();
      used[(f * bh + i / m.atlasWidth / 4) * bw + i % m.atlasWidth / 4] = 1;
    }
  return used;
}

} // namespace

ImpostorTexels decodeTexels(const Impostor &m, uint32_t frame) {
  ImpostorTexels t;
  t.width = m.atlasWidth, t.height = m.atlasHeight;
  const size_t texels = m.frameTexels(), blocks = bc5Bytes(m.atlasWidth, m.atlasHeight);
  t.oct.resize(texels * 2);
  decodeBc5(&m.normals[frame * blocks], m.atlasWidth, m.atlasHeight, t.oct.data());
  if (!m.uvs.empty()) {
    t.uv.resize(texels * 2);
    decodeBc5(&m.uvs[frame * blocks], m.atlasWidth, m.atlasHeight, t.uv.data());
  }
  t.regions = std::span<const uint8_t>(m.regions).subspan(frame * texels, texels);
  return t;
}

std::vector<uint8_t> encode(const Impostor &m) {
  ByteWriter w;
  w.putString(m.clip);
  w.putString(m.outfit);
  w.put<float>(m.startTime);
  w.put<float>(m.frameStep);
  for (uint32_t v : {m.frames, m.azimuths, m.elevations, m.texels})
    w.put<uint32_t>(v);
  w.put<uint8_t>(m.mirrored ? 1 : 0);
  for (float f : m.sphere)
    w.put<float>(f);
  w.put<uint32_t>(m.atlasWidth);
  w.put<uint32_t>(m.atlasHeight);
  w.put<uint64_t>(m.views.size());
  for (const auto &v : m.views) {
    for (uint16_t u : {v.x, v.y, v.width, v.height})
      w.put<uint16_t>(u);
    w.put<float>(v.pivotX);
    w.put<float>(v.pivotY);
    w.put<float>(v.planeOffset);
    w.put<float>(v.slopeX);
    w.put<float>(v.slopeY);
  }
  // Regions first: they say which blocks hold a covered texel; only those blocks are stored.
  w.putArray(m.regions);
  const auto used = usedBlocks(m);
  for (const auto *plane : {&m.normals, &m.uvs}) {
    std::vector<uint8_t> stored;
    for (size_t b = 0; b < used.size() && !plane->empty(); ++b)
      if (used[b])
        stored.insert(stored.end(), plane->begin() + long(b * kBc5BlockBytes),
                      plane->begin() + long((b + 1) * kBc5BlockBytes));
    w.put<uint8_t>(plane->empty() ? 0 : 1);
    w.putArray(stored);
  }
  return w.take();
}

namespace {

// Chunk versions 1 and 2 kept RGBA8 texels (normal * 0.5 + 0.5, region id + 1) and, with UVs,
// RGBA16 ones (u, v, region, 0): read and encoded as version 3 keeps them, the atlas padded to
// whole blocks, so older packs still load and diff.
void readUncompressedAtlases(ByteReader &r, Impostor &m, uint64_t texels) {
  const auto rgba = r.getArray<uint8_t>("atlases", texels * 4);
  if (rgba.size() != texels * 4)
    r.fail("atlases", "size is not frames x width x height x 4");
  const auto uv16 = r.getArray<uint16_t>("uv atlases", texels * 4);
  if (!uv16.empty() && uv16.size() != texels * 4)
    r.fail("uv atlases", "size is not frames x width x height x 4");
  const uint32_t w = m.atlasWidth, h = m.atlasHeight;
  m.atlasWidth = (w + 3) / 4 * 4, m.atlasHeight = (h + 3) / 4 * 4;
  const size_t per = m.frameTexels();
  std::vector<float> oct(per * 2, 0.5f), uv(uv16.empty() ? 0 : per * 2, 0.0f);
  m.regions.assign(per * m.frames, 0);
  for (uint32_t f = 0; f < m.frames; ++f) {
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x) {
        const size_t from = (size_t(f) * h + y) * w + x, i = size_t(y) * m.atlasWidth + x;
        m.regions[f * per + i] = rgba[from * 4 + 3];
        std::array<float, 3> n{};
        for (size_t k = 0; k < 3; ++k)
          n[k] = rgba[from * 4 + k] / 255.0f * 2 - 1;
        const auto o = octEncode(n);
        oct[i * 2] = o[0], oct[i * 2 + 1] = o[1];
        for (size_t k = 0; k < uv.size() / per; ++k)
          uv[i * 2 + k] = uv16[from * 4 + k] / 65535.0f;
      }
    const uint8_t *used = &m.regions[f * per];
    auto n = encodeBc5(oct.data(), used, m.atlasWidth, m.atlasHeight);
    m.normals.insert(m.normals.end(), n.begin(), n.end());
    if (!uv.empty()) {
      auto u = encodeBc5(uv.data(), used, m.atlasWidth, m.atlasHeight);
      m.uvs.insert(m.uvs.end(), u.begin(), u.end());
    }
  }
}

} // namespace

Impostor decodeImpostor(std::span<const uint8_t> bytes, uint32_t version,
                        const std::string &context) {
  if (version < 1 || version > kImpostorVersion)
    throw Error(context + ": chunk version " + std::to_string(version) + " is not supported");
  ByteReader r(bytes, context);
  Impostor m;
  m.clip = r.getString("clip");
  if (version >= 2)
    m.outfit = r.getString("outfit");
  m.startTime = r.get<float>("start time");
  m.frameStep = r.get<float>("frame step");
  m.frames = r.get<uint32_t>("frames");
  m.azimuths = r.get<uint32_t>("azimuths");
  m.elevations = r.get<uint32_t>("elevations");
  m.texels = r.get<uint32_t>("texels");
  uint8_t mirrored = r.get<uint8_t>("mirrored");
  if (mirrored > 1)
    r.fail("mirrored", "flag is " + std::to_string(mirrored));
  m.mirrored = mirrored == 1;
  if (!std::isfinite(m.startTime) || !std::isfinite(m.frameStep) || m.frameStep < 0)
    r.fail("start time/frame step", "not finite or negative");
  if (m.frames == 0 || m.frames > 4096 || m.azimuths == 0 || m.azimuths > 256 ||
      m.elevations == 0 || m.elevations > 64)
    r.fail("frames/azimuths/elevations", "out of range (1..4096, 1..256, 1..64)");
  if (m.texels < 4 || m.texels > 4096)
    r.fail("texels", std::to_string(m.texels) + " is out of range 4..4096");
  for (float &f : m.sphere)
    f = r.get<float>("sphere");
  if (!(m.sphere[3] > 0) || !std::isfinite(m.sphere[0] + m.sphere[1] + m.sphere[2] + m.sphere[3]))
    r.fail("sphere", "not finite or radius not positive");
  m.atlasWidth = r.get<uint32_t>("atlas width");
  m.atlasHeight = r.get<uint32_t>("atlas height");
  if (m.atlasWidth == 0 || m.atlasHeight == 0 || m.atlasWidth > 16384 || m.atlasHeight > 16384)
    r.fail("atlas width/height", "out of range 1..16384");
  if (version >= 3 && (m.atlasWidth % 4 != 0 || m.atlasHeight % 4 != 0))
    r.fail("atlas width/height", "not multiples of 4 (whole blocks)");
  uint64_t count = r.get<uint64_t>("view count");
  if (m.mirrored && (m.azimuths % 2 != 0 || m.frames % 2 != 0))
    r.fail("mirrored", "needs even azimuth and frame counts");
  if (count != uint64_t(m.frames) * m.storedAzimuths() * m.elevations)
    r.fail("view count", std::to_string(count) + " is not frames x stored azimuths x elevations");
  m.views.resize(count);
  for (auto &v : m.views) {
    v.x = r.get<uint16_t>("view x");
    v.y = r.get<uint16_t>("view y");
    v.width = r.get<uint16_t>("view width");
    v.height = r.get<uint16_t>("view height");
    v.pivotX = r.get<float>("view pivot x");
    v.pivotY = r.get<float>("view pivot y");
    v.planeOffset = r.get<float>("view plane offset");
    if (version >= 4) {
      v.slopeX = r.get<float>("view plane slope x");
      v.slopeY = r.get<float>("view plane slope y");
      if (!(std::abs(v.slopeX) <= kMaxPlaneSlope && std::abs(v.slopeY) <= kMaxPlaneSlope))
        r.fail("view plane slope", "not finite or steeper than " + std::to_string(kMaxPlaneSlope));
    }
    if (uint32_t(v.x) + v.width > m.atlasWidth || uint32_t(v.y) + v.height > m.atlasHeight)
      r.fail("view rectangle", "lies outside the atlas");
    if (!std::isfinite(v.pivotX) || !std::isfinite(v.pivotY) || !std::isfinite(v.planeOffset))
      r.fail("view pivot", "not finite");
  }
  const uint64_t blocks = uint64_t(m.frames) * bc5Bytes(m.atlasWidth, m.atlasHeight);
  const uint64_t texels = uint64_t(m.frames) * m.atlasWidth * m.atlasHeight;
  if (version < 3) {
    readUncompressedAtlases(r, m, texels);
    r.expectEnd();
    return m;
  }
  m.regions = r.getArray<uint8_t>("regions", texels);
  if (m.regions.size() != texels)
    r.fail("regions", "size is not frames x width x height");
  const auto used = usedBlocks(m);
  const uint64_t stored = uint64_t(std::count(used.begin(), used.end(), 1)) * kBc5BlockBytes;
  for (auto [plane, name] : {std::pair{&m.normals, "normals"}, std::pair{&m.uvs, "uvs"}}) {
    const uint8_t present = r.get<uint8_t>(name);
    const auto bytes = r.getArray<uint8_t>(name, stored);
    if (present > 1 || (present == 0 && !bytes.empty()) || (present == 1 && bytes.size() != stored))
      r.fail(name, "not the blocks that hold a covered texel, BC5");
    if (present == 0)
      continue;
    plane->assign(blocks, 0); // a block with no covered texel reads zero
    for (size_t b = 0, k = 0; b < used.size(); ++b)
      if (used[b])
        std::copy_n(&bytes[(k++) * kBc5BlockBytes], kBc5BlockBytes,
                    plane->begin() + long(b * kBc5BlockBytes));
  }
  if (m.normals.empty())
    r.fail("normals", "missing");
  r.expectEnd();
  return m;
}

ImpostorPack loadImpostorPack(const Reader &reader) {
  auto ctx = [&](uint32_t type) {
    return "pack '" + reader.name() + "', chunk " + fourccName(type);
  };
  const ChunkEntry &prov = reader.require(kProvenance);
  codecOf(prov, ctx(kProvenance));
  ImpostorPack p;
  p.provenance = decodeProvenance(reader.payload(prov), ctx(kProvenance));
  const ChunkEntry &impostor = reader.require(kImpostor);
  p.impostor = decodeImpostor(reader.payload(impostor), impostor.version, ctx(kImpostor));
  return p;
}

std::vector<uint8_t> packBytes(const ImpostorPack &p) {
  Writer w;
  w.add(kProvenance, kChunkVersion, encode(p.provenance));
  w.add(kImpostor, kImpostorVersion, encode(p.impostor));
  return w.bytes();
}

} // namespace crowd::pack
