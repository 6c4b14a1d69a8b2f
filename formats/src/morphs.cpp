#include <cmath>

#include "crowd/formats/bytes.h"
#include "crowd/formats/chunks.h"
#include "crowd/formats/limits.h"

namespace crowd::pack {

std::vector<uint8_t> encode(const Morphs &m) {
  ByteWriter w;
  w.put<uint32_t>(m.vertexCount);
  w.put<uint32_t>(uint32_t(m.targets.size()));
  for (const auto &t : m.targets) {
    w.putString(t.name);
    w.put<uint32_t>(t.firstVertex);
    w.put<uint32_t>(t.vertexCount);
  }
  w.putArray(m.offsets);
  std::vector<float> slots;
  for (const auto &s : m.slots)
    slots.insert(slots.end(), {s.target, s.weight});
  w.putArray(slots);
  return w.take();
}

Morphs decodeMorphs(std::span<const uint8_t> bytes, const std::string &context) {
  ByteReader r(bytes, context);
  Morphs m;
  m.vertexCount = r.get<uint32_t>("vertex count");
  const uint32_t n = r.get<uint32_t>("target count");
  if (n == 0 || n > limits::kMorphTargets)
    r.fail("target count",
           std::to_string(n) + " is out of range 1.." + std::to_string(limits::kMorphTargets));
  uint64_t offsets = 0;
  for (uint32_t i = 0; i < n; ++i) {
    Morphs::Target t;
    t.name = r.getString("target name");
    t.firstVertex = r.get<uint32_t>("first vertex");
    t.vertexCount = r.get<uint32_t>("target vertex count");
    if (uint64_t(t.firstVertex) + t.vertexCount > m.vertexCount)
      r.fail("first vertex", "target " + std::to_string(i) + " runs past the mesh's " +
                                 std::to_string(m.vertexCount) + " vertices");
    t.firstOffset = offsets;
    offsets += uint64_t(t.vertexCount) * 8;
    m.targets.push_back(std::move(t));
  }
  if (offsets > limits::kMorphOffsets * 8)
    r.fail("target vertex count",
           "the ranges hold over " + std::to_string(limits::kMorphOffsets) + " vertices");
  m.offsets = r.getArray<float>("offsets", offsets);
  if (m.offsets.size() != offsets)
    r.fail("offsets", std::to_string(m.offsets.size()) + " values, the ranges need " +
                          std::to_string(offsets));
  for (float f : m.offsets)
    if (!std::isfinite(f))
      r.fail("offsets", "a value is not finite");
  const auto slots = r.getArray<float>("slots", limits::kChunkElements);
  if (slots.empty() || slots.size() % (2 * kMorphSlots) != 0)
    r.fail("slots", "not " + std::to_string(kMorphSlots) + " (target, weight) pairs per frame");
  for (size_t i = 0; i < slots.size(); i += 2) {
    const float target = slots[i], weight = slots[i + 1];
    if (!std::isfinite(weight) || !(target >= 0 && target < float(n)) ||
        target != std::floor(target))
      r.fail("slots", "slot " + std::to_string(i / 2) + " names no target or has no weight");
    m.slots.push_back({target, weight});
  }
  r.expectEnd();
  return m;
}

} // namespace crowd::pack
