#include "vertex_weld.h"

#include "float_key.h"

namespace crowd::lod {

std::vector<uint32_t> vertexKey(const SkinnedMesh &m, uint32_t v, uint32_t part, bool normals) {
  std::vector<uint32_t> key{part};
  for (int k = 0; k < 3; ++k)
    putBits(key, m.positions[v][k]);
  if (normals)
    for (int k = 0; k < 3; ++k)
      putBits(key, m.normals[v][k]);
  if (!m.uvs.empty())
    putBits(key, m.uvs[v].x), putBits(key, m.uvs[v].y);
  for (int k = 0; k < 4; ++k)
    key.push_back(m.joints[v][size_t(k)]), putBits(key, m.weights[v][k]);
  for (const auto &target : m.morphs)
    for (int k = 0; k < 3; ++k) {
      putBits(key, target.positions[v][k]);
      if (normals)
        putBits(key, target.normals[v][k]);
    }
  return key;
}

std::vector<uint32_t> weldInto(SkinnedMesh &m, const std::vector<uint32_t> &into) {
  const size_t V = m.positions.size();
  std::vector<uint32_t> newIndex(V, UINT32_MAX), was;
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
  return was;
}

} // namespace crowd::lod
