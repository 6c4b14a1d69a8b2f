#include "vertex_weld.h"

#include "float_key.h"

namespace crowd::lod {

void CopyFinder::key(uint32_t v, uint32_t part, std::vector<uint32_t> &key) const {
  key.clear();
  key.push_back(part);
  for (int k = 0; k < 3; ++k)
    putBits(key, m_.positions[v][k]);
  if (normals_)
    for (int k = 0; k < 3; ++k)
      putBits(key, m_.normals[v][k]);
  if (!m_.uvs.empty() && (part >= m_.parts.size() || m_.parts[part].textured))
    putBits(key, m_.uvs[v].x), putBits(key, m_.uvs[v].y);
  for (int k = 0; k < 4; ++k)
    key.push_back(m_.joints[v][size_t(k)]), putBits(key, m_.weights[v][k]);
  for (const auto &target : m_.morphs)
    for (int k = 0; k < 3; ++k) {
      putBits(key, target.positions[v][k]);
      if (normals_)
        putBits(key, target.normals[v][k]);
    }
}

uint32_t CopyFinder::firstOf(uint32_t v, uint32_t part) {
  key(v, part, key_);
  uint64_t h = 1469598103934665603ull; // FNV-1a over the words
  for (uint32_t w : key_)
    h = (h ^ w) * 1099511628211ull;
  const auto [from, to] = firsts_.equal_range(h);
  for (auto it = from; it != to; ++it) {
    key(it->second.first, it->second.second, other_);
    if (other_ == key_)
      return it->second.first;
  }
  firsts_.emplace(h, std::make_pair(v, part));
  return v;
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
