#include "crowd/formats/cloth.h"

#include <cmath>

#include "crowd/formats/bytes.h"
#include "crowd/formats/limits.h"

namespace crowd::pack {

uint32_t ClothLoop::frameCount() const {
  return sourceVertices.empty() ? 0 : uint32_t(positions.size() / (3 * sourceVertices.size()));
}

std::array<float, 3> ClothLoop::position(uint32_t frame, uint32_t vertex) const {
  const size_t i = (size_t(frame) * vertexCount() + vertex) * 3;
  return {origin[0] + positions[i] * step[0], origin[1] + positions[i + 1] * step[1],
          origin[2] + positions[i + 2] * step[2]};
}

std::vector<uint8_t> encode(const ClothLoop &c) {
  ByteWriter w;
  w.putString(c.outfit);
  w.putString(c.garment);
  w.putString(c.clip);
  w.put<float>(c.fps);
  w.put<uint32_t>(c.cycles);
  w.put<uint32_t>(c.cacheStart);
  w.put<uint32_t>(c.blendFrames);
  for (int k = 0; k < 3; ++k)
    w.put<float>(c.origin[size_t(k)]);
  for (int k = 0; k < 3; ++k)
    w.put<float>(c.step[size_t(k)]);
  w.putArray(c.sourceVertices);
  w.putArray(c.positions);
  return w.take();
}

ClothLoop decodeClothLoop(std::span<const uint8_t> bytes, const std::string &context) {
  ByteReader r(bytes, context);
  ClothLoop c;
  c.outfit = r.getString("outfit");
  c.garment = r.getString("garment");
  c.clip = r.getString("clip");
  if (c.garment.empty() || c.clip.empty())
    r.fail("garment", "the garment and the clip must be named");
  c.fps = r.get<float>("fps");
  if (!(c.fps > 0 && c.fps <= 1000))
    r.fail("fps", "not in (0, 1000]");
  c.cycles = r.get<uint32_t>("cycles");
  if (c.cycles == 0)
    r.fail("cycles", "a loop spans at least one clip cycle");
  c.cacheStart = r.get<uint32_t>("cache start");
  c.blendFrames = r.get<uint32_t>("blend frames");
  for (auto *v : {&c.origin, &c.step})
    for (auto &x : *v) {
      x = r.get<float>("box");
      if (!std::isfinite(x))
        r.fail("box", "a value is not finite");
    }
  c.sourceVertices = r.getArray<uint32_t>("source vertices", limits::kVertices);
  if (c.sourceVertices.empty())
    r.fail("source vertices", "a garment without vertices");
  for (size_t i = 1; i < c.sourceVertices.size(); ++i)
    if (c.sourceVertices[i] <= c.sourceVertices[i - 1])
      r.fail("source vertices", "not ascending");
  c.positions = r.getArray<uint16_t>("positions", limits::kChunkElements);
  const uint64_t perFrame = 3 * uint64_t(c.sourceVertices.size());
  if (c.positions.empty() || c.positions.size() % perFrame != 0)
    r.fail("positions",
           "not whole frames of " + std::to_string(c.sourceVertices.size()) + " vertices");
  if (c.frameCount() > limits::kCacheFrames || c.blendFrames >= c.frameCount())
    r.fail("positions", std::to_string(c.frameCount()) + " frames, blend " +
                            std::to_string(c.blendFrames) + ": out of range");
  r.expectEnd();
  return c;
}

} // namespace crowd::pack
