#include "crowd/formats/cloth.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "crowd/formats/bytes.h"
#include "crowd/formats/error.h"
#include "crowd/formats/limits.h"

namespace crowd::pack {

uint32_t ClothLoop::frameCount() const {
  return vertexCount() == 0 ? 0 : uint32_t(positions.size() / (3 * size_t(vertexCount())));
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
  w.putArray(encode(c.sources));
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
  c.sources = decodeSourceMap(r.getArray<uint8_t>("sources", limits::kChunkElements),
                              context + ", sources");
  const uint64_t n = c.sources.vertexCount();
  if (n == 0 || n > limits::kVertices)
    r.fail("sources", std::to_string(n) + " vertices: out of range");
  const auto expanded = c.sources.expand();
  if (std::any_of(expanded.begin(), expanded.end(),
                  [](const VertexSource &s) { return s.vertex < 0 || s.file != 0; }))
    r.fail("sources", "a vertex without a source in the outfit's file");
  c.positions = r.getArray<uint16_t>("positions", limits::kChunkElements);
  if (c.positions.empty() || c.positions.size() % (3 * n) != 0)
    r.fail("positions", "not whole frames of " + std::to_string(n) + " vertices");
  if (c.frameCount() > limits::kCacheFrames || c.blendFrames >= c.frameCount())
    r.fail("positions", std::to_string(c.frameCount()) + " frames, blend " +
                            std::to_string(c.blendFrames) + ": out of range");
  r.expectEnd();
  return c;
}

std::vector<int32_t> clothVertexOf(const AnimationPack &body, const ClothLoop &loop,
                                   const std::string &context) {
  if (!body.sources || !body.outfits)
    throw Error(context + ": the pack has no " +
                (body.sources ? "outfit table" : "vertex sources") +
                " to place the loop's vertices with");
  const auto &outfits = body.outfits->outfits;
  const auto it = std::find_if(outfits.begin(), outfits.end(),
                               [&](const Outfits::Outfit &o) { return o.name == loop.outfit; });
  if (it == outfits.end())
    throw Error(context + ": outfit '" + loop.outfit + "' is not in the pack's outfit table");
  const int32_t file = int32_t(it - outfits.begin()) + 1;
  std::map<VertexSource, int32_t> index;
  int32_t k = 0;
  for (VertexSource s : loop.sources.expand()) {
    s.file = file;
    index.emplace(s, k++);
  }
  std::vector<int32_t> of;
  std::vector<bool> placed(size_t(k), false);
  for (const VertexSource &s : body.sources->expand()) {
    const auto found = index.find(s);
    of.push_back(found == index.end() ? -1 : found->second);
    if (found != index.end())
      placed[size_t(found->second)] = true;
  }
  const auto missing = std::count(placed.begin(), placed.end(), false);
  if (missing > 0)
    throw Error(context + ": " + std::to_string(missing) + " of the loop's " + std::to_string(k) +
                " vertices are not in the mesh (a loop of another outfit file, or of another "
                "garment)");
  return of;
}

} // namespace crowd::pack
