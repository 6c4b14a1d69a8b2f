// The outfit bake's quick ray-triangle test, ahead of CGAL's in visibility.cpp: most rays the
// blocker cache tries are answered here; only those near an edge, near the origin or nearly
// parallel to the triangle go to CGAL. tests/unit/ray_crossing_test.cpp checks every sure answer
// against CGAL's, on rays aimed at the triangles' edges, grazing them and starting on them.
#pragma once
#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

namespace crowd::outfit {

// Whether the ray crosses the triangle, by Moller-Trumbore with margins: kYes well inside it
// (barycentric margin 1e-7) and well ahead of the origin, kNo well outside it or well behind the
// origin, kUnsure near an edge, near the origin or nearly parallel to the plane: the caller asks
// CGAL then, so the answers here are the ones CGAL's test gives (the sample outfits' packs are
// byte-identical). About 2 of 5 rays the blocker cache tries miss: they are answered here, not
// in CGAL, with each triangle's edges kept (Edges).
enum class Crossing { kNo, kYes, kUnsure };
// A triangle as crossing() reads it: a corner, the edges from it, their squared lengths, and
// its parallel guard (below).
struct Edges {
  glm::dvec3 a, e1, e2;
  double l1, l2, guard;
};
// reach: at least the distance from a to any ray origin crossing() will be given with it.
inline Edges edgesOf(const glm::dvec3 &a, const glm::dvec3 &b, const glm::dvec3 &c, double reach) {
  const glm::dvec3 e1 = b - a, e2 = c - a;
  const double l1 = glm::dot(e1, e1), l2 = glm::dot(e2, e2);
  return {a, e1, e2, l1, l2, l1 * l2 * std::max(1.0, reach * reach / std::min(l1, l2))};
}
// The ray from o along w.
inline Crossing crossing(const glm::dvec3 &o, const glm::dvec3 &w, const Edges &t) {
  const glm::dvec3 pv = glm::cross(w, t.e2);
  const double det = glm::dot(t.e1, pv);
  constexpr double margin = 1e-7;
  // Nearly parallel to the plane, or degenerate: the sine of the ray's angle to the plane
  // (det / (|w| |e1| |e2|), about) at most 1e-7 times the reach in the shorter edge's lengths
  // (at least 1): rounding moves the crossing by about 1e-16 of the origin's distance over the
  // sine, and CGAL's test by as much.
  const double w2 = glm::dot(w, w);
  if (!(det * det > margin * margin * w2 * t.guard))
    return Crossing::kUnsure;
  const glm::dvec3 tv = o - t.a;
  const double bu = glm::dot(tv, pv) / det;
  if (bu < -margin || bu > 1 + margin)
    return Crossing::kNo;
  const glm::dvec3 qv = glm::cross(tv, t.e1);
  const double bv = glm::dot(w, qv) / det;
  if (bv < -margin || bu + bv > 1 + margin)
    return Crossing::kNo;
  const double ahead = glm::dot(t.e2, qv) / det * std::sqrt(w2),
               near = margin * (std::sqrt(t.l1) + std::sqrt(t.l2));
  if (ahead < -near)
    return Crossing::kNo;
  if (bu > margin && bv > margin && bu + bv < 1 - margin && ahead > near)
    return Crossing::kYes;
  return Crossing::kUnsure;
}

} // namespace crowd::outfit
