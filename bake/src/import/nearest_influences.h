// A skinned vertex no joint weighs (an exporter's unpainted button or eye) is repaired, not
// refused: it takes the influences of the nearest weighted vertex of its primitive, which is what
// a painter's "transfer weights from nearest" would give it. three.js would draw it at the origin
// and Blender unskinned; neither follows the character.
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>

namespace crowd::gltf {

// For every vertex whose list is empty, a copy of the list of the nearest vertex (positions xyz,
// ties to the lower index) whose list was not: a sweep along one axis, pruned by the best so far.
// Returns how many were filled; none are where no list has anything (the caller's error).
template <class List>
size_t borrowNearestInfluences(std::vector<List> &lists, const std::vector<double> &xyz) {
  std::vector<uint32_t> weighted; // along the axis where they spread most, then by index
  double low[3] = {1e300, 1e300, 1e300}, high[3] = {-1e300, -1e300, -1e300};
  for (uint32_t v = 0; v < lists.size(); ++v)
    if (!lists[v].empty()) {
      weighted.push_back(v);
      for (int k = 0; k < 3; ++k)
        low[k] = std::min(low[k], xyz[3 * v + k]), high[k] = std::max(high[k], xyz[3 * v + k]);
    }
  if (weighted.empty() || weighted.size() == lists.size())
    return 0;
  int axis = 0; // a flat mesh would otherwise sweep along an axis it has no extent in
  for (int k = 1; k < 3; ++k)
    if (high[k] - low[k] > high[axis] - low[axis])
      axis = k;
  auto along = [&](uint32_t v) { return xyz[3 * v + size_t(axis)]; };
  std::sort(weighted.begin(), weighted.end(), [&](uint32_t a, uint32_t b) {
    return along(a) != along(b) ? along(a) < along(b) : a < b;
  });
  // Only empty lists are filled and only `weighted` ones read: no copy of the lists is needed.
  size_t filled = 0;
  for (uint32_t v = 0; v < lists.size(); ++v) {
    if (!lists[v].empty())
      continue;
    auto distance2 = [&](uint32_t w) {
      double d = 0;
      for (int k = 0; k < 3; ++k)
        d += (xyz[3 * w + k] - xyz[3 * v + k]) * (xyz[3 * w + k] - xyz[3 * v + k]);
      return d;
    };
    // Outwards from v along the axis, both ways, while the gap along it is under the best.
    const auto at = std::lower_bound(weighted.begin(), weighted.end(), along(v),
                                     [&](uint32_t w, double x) { return along(w) < x; });
    double best = -1;
    uint32_t nearest = 0;
    auto consider = [&](uint32_t w) {
      const double d = distance2(w);
      if (best < 0 || d < best || (d == best && w < nearest))
        best = d, nearest = w;
    };
    auto gap2 = [&](uint32_t w) { return (along(w) - along(v)) * (along(w) - along(v)); };
    for (auto it = at; it != weighted.end() && (best < 0 || gap2(*it) <= best); ++it)
      consider(*it);
    for (auto it = at; it != weighted.begin() && (best < 0 || gap2(*(it - 1)) <= best); --it)
      consider(*(it - 1));
    lists[v] = lists[nearest];
    ++filled;
  }
  return filled;
}

} // namespace crowd::gltf
