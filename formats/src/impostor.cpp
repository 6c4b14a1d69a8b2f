#include "crowd/formats/impostor.h"

#include <cmath>

#include "crowd/formats/bytes.h"
#include "crowd/formats/error.h"
#include "crowd/formats/registry.h"

namespace crowd::pack {

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
  }
  w.putArray(m.atlases);
  w.putArray(m.uvAtlases);
  return w.take();
}

Impostor decodeImpostor(std::span<const uint8_t> bytes, uint32_t version,
                        const std::string &context) {
  if (version != 1 && version != kImpostorVersion)
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
    if (uint32_t(v.x) + v.width > m.atlasWidth || uint32_t(v.y) + v.height > m.atlasHeight)
      r.fail("view rectangle", "lies outside the atlas");
    if (!std::isfinite(v.pivotX) || !std::isfinite(v.pivotY) || !std::isfinite(v.planeOffset))
      r.fail("view pivot", "not finite");
  }
  uint64_t expected = uint64_t(m.frames) * m.atlasWidth * m.atlasHeight * 4;
  m.atlases = r.getArray<uint8_t>("atlases", expected);
  if (m.atlases.size() != expected)
    r.fail("atlases", "size is not frames x width x height x 4");
  m.uvAtlases = r.getArray<uint16_t>("uv atlases", expected);
  if (!m.uvAtlases.empty() && m.uvAtlases.size() != expected)
    r.fail("uv atlases", "size is not frames x width x height x 4");
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
