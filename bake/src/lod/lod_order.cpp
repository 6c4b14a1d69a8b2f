#include "lod_order.h"

namespace crowd::lod {

std::vector<uint32_t> numberVertices(const FanMesh &fan, const Removals &removals,
                                     const std::vector<uint32_t> &indices, LodResult &r,
                                     size_t &isolated) {
  const size_t V = fan.source.size();
  std::vector<uint8_t> used(V, 0);
  for (const auto &c : fan.render)
    for (uint32_t rv : c)
      used[rv] = 1;
  for (uint32_t i : indices)
    used[i] |= 2; // referenced by the input at all
  std::vector<uint32_t> newIndex(V, UINT32_MAX);
  for (uint32_t v = 0; v < V; ++v)
    if (used[v] & 1 && removals.target[v] == UINT32_MAX)
      newIndex[v] = uint32_t(r.order.size()), r.order.push_back(fan.source[v]);
  r.floorVertices = uint32_t(r.order.size());
  for (auto it = removals.removed.rbegin(); it != removals.removed.rend(); ++it)
    newIndex[*it] = uint32_t(r.order.size()), r.order.push_back(fan.source[*it]);
  isolated = 0;
  for (uint32_t v = 0; v < V; ++v)
    if (newIndex[v] == UINT32_MAX) {
      newIndex[v] = uint32_t(r.order.size()), r.order.push_back(fan.source[v]);
      isolated += !(used[v] & 2);
    }
  r.collapse.resize(r.order.size());
  r.error.assign(r.order.size(), 0.0f);
  r.colourChange.assign(r.order.size(), 0.0f);
  for (uint32_t v = 0; v < V; ++v) {
    const uint32_t k = newIndex[v], target = removals.target[v];
    r.collapse[k] = target != UINT32_MAX ? newIndex[target] : (k < r.floorVertices ? k : 0);
    r.error[k] = removals.cost[v];
    r.colourChange[k] = removals.colour[v];
  }
  return newIndex;
}

void orderTriangles(const FanMesh &fan, const std::vector<std::array<uint32_t, 3>> &initialCorner,
                    const Removals &removals, const std::vector<uint32_t> &newIndex, LodResult &r) {
  const size_t F = initialCorner.size(), V = newIndex.size();
  // The lower its killer's new index, the later a triangle goes.
  auto death = [&](uint32_t f) {
    const int64_t killer = removals.killer[f];
    return killer < 0 ? uint32_t(UINT32_MAX) : newIndex[size_t(killer)];
  };
  auto rank = [&](uint32_t f) { return removals.killer[f] < 0 ? size_t(0) : size_t(death(f)) + 1; };
  std::vector<uint32_t> faces(F), start(V + 2, 0); // sorted by rank, stable: a counting sort
  for (uint32_t f = 0; f < F; ++f)
    ++start[rank(f) + 1];
  for (size_t k = 1; k < start.size(); ++k)
    start[k] += start[k - 1];
  for (uint32_t f = 0; f < F; ++f)
    faces[start[rank(f)]++] = f;
  // A face is alive at v vertices while its killer (new index d) is < v.
  r.triangleCount.assign(r.order.size() + 1, 0);
  for (uint32_t f : faces) {
    for (int k = 0; k < 3; ++k)
      r.indices.push_back(newIndex[initialCorner[f][size_t(k)]]);
    const uint32_t d = death(f);
    ++r.triangleCount[d == UINT32_MAX ? 0 : d + 1];
    r.source.push_back(fan.inputTriangle[f]);
    r.killedBy.push_back(d);
  }
  for (size_t v = 1; v < r.triangleCount.size(); ++v)
    r.triangleCount[v] += r.triangleCount[v - 1];
}

} // namespace crowd::lod
