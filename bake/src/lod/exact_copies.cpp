#include <map>

#include "crowd/bake/character.h"
#include "crowd/bake/lod_bake.h"
#include "float_key.h"

namespace crowd {

using lod::putBits;

std::vector<uint32_t> weldExactCopies(SkinnedMesh &m, Reporter &reporter,
                                      const std::vector<uint32_t> &keep) {
  const size_t V = m.positions.size();
  std::vector<uint32_t> was(V);
  for (uint32_t v = 0; v < V; ++v)
    was[v] = v;
  // Each vertex's sub-mesh; kNone where unused, kMixed where two sub-meshes use it (not welded:
  // sub-meshes keep their own borders, as lodTriangles welds them).
  constexpr uint32_t kNone = UINT32_MAX, kMixed = UINT32_MAX - 1;
  const std::vector<uint32_t> partOf = triangleParts(m);
  std::vector<uint32_t> part(V, kNone);
  for (size_t i = 0; i < m.indices.size(); ++i) {
    uint32_t &p = part[m.indices[i]];
    p = p == kNone || p == partOf[i / 3] ? partOf[i / 3] : kMixed;
  }
  for (uint32_t v : keep)
    if (v < V)
      part[v] = kMixed;
  std::map<std::vector<uint32_t>, uint32_t> firstOf;
  std::vector<uint32_t> into(V);
  size_t copies = 0;
  for (uint32_t v = 0; v < V; ++v) {
    into[v] = v;
    if (part[v] == kNone || part[v] == kMixed)
      continue;
    std::vector<uint32_t> key{part[v]};
    for (int k = 0; k < 3; ++k)
      putBits(key, m.positions[v][k]), putBits(key, m.normals[v][k]);
    if (!m.uvs.empty())
      putBits(key, m.uvs[v].x), putBits(key, m.uvs[v].y);
    for (int k = 0; k < 4; ++k)
      key.push_back(m.joints[v][size_t(k)]), putBits(key, m.weights[v][k]);
    for (const auto &target : m.morphs)
      for (int k = 0; k < 3; ++k)
        putBits(key, target.positions[v][k]), putBits(key, target.normals[v][k]);
    into[v] = firstOf.try_emplace(std::move(key), v).first->second;
    copies += into[v] != v;
  }
  if (copies == 0)
    return was;

  // Keep the first of each, in input order.
  std::vector<uint32_t> newIndex(V, UINT32_MAX);
  was.clear();
  for (uint32_t v = 0; v < V; ++v)
    if (into[v] == v)
      newIndex[v] = uint32_t(was.size()), was.push_back(v);
  for (uint32_t &i : m.indices)
    i = newIndex[into[i]];
  auto keepOnly = [&](auto &values) {
    auto old = std::move(values);
    values.clear();
    for (uint32_t v : was)
      values.push_back(old[v]);
  };
  keepOnly(m.positions), keepOnly(m.normals), keepOnly(m.joints), keepOnly(m.weights);
  if (!m.uvs.empty())
    keepOnly(m.uvs);
  if (!m.sources.empty())
    keepOnly(m.sources);
  for (auto &target : m.morphs)
    keepOnly(target.positions), keepOnly(target.normals);
  reporter.warn("exact_copies",
                std::to_string(copies) +
                    " vertices repeat another exactly (every attribute the same, as a mesh "
                    "written without shared vertices has them): welded, so the LOD can collapse "
                    "across them; the drawn mesh is the same",
                copies);
  return was;
}

} // namespace crowd
