#include "lod_distance.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include "crowd/bake/evaluate.h"
#include "crowd/bake/import.h"

namespace crowd::bench {
namespace {

using K = CGAL::Simple_cartesian<double>;
using Triangle = K::Triangle_3;
using Tree = CGAL::AABB_tree<
    CGAL::AABB_traits<K, CGAL::AABB_triangle_primitive<K, std::vector<Triangle>::const_iterator>>>;

std::vector<Triangle> soup(const std::vector<glm::dvec3> &p, const std::vector<uint32_t> &idx) {
  std::vector<Triangle> t;
  for (size_t i = 0; i + 2 < idx.size(); i += 3) {
    auto P = [&](uint32_t v) { return K::Point_3(p[v].x, p[v].y, p[v].z); };
    Triangle tri(P(idx[i]), P(idx[i + 1]), P(idx[i + 2]));
    if (!tri.is_degenerate())
      t.push_back(tri);
  }
  return t;
}

// Largest distance from points of `a` to the surface `b`.
double oneSided(const std::vector<Triangle> &a, const std::vector<Triangle> &b, int samples) {
  Tree tree(b.begin(), b.end());
  tree.accelerate_distance_queries();
  double worst = 0, total = 0;
  std::vector<double> cumulative;
  for (const auto &t : a)
    cumulative.push_back(total += std::sqrt(t.squared_area()));
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(0, 1);
  auto probe = [&](const K::Point_3 &p) {
    worst = std::max(worst, std::sqrt(tree.squared_distance(p)));
  };
  for (const auto &t : a)
    for (int k = 0; k < 3; ++k)
      probe(t[k]);
  for (int s = 0; s < samples; ++s) {
    size_t i = size_t(std::lower_bound(cumulative.begin(), cumulative.end(), u(rng) * total) -
                      cumulative.begin());
    const Triangle &t = a[std::min(i, a.size() - 1)];
    double r1 = std::sqrt(u(rng)), r2 = u(rng);
    probe(CGAL::barycenter(t[0], 1 - r1, t[1], r1 * (1 - r2), t[2], r1 * r2));
  }
  return worst;
}

double hausdorff(const std::vector<glm::dvec3> &p, const std::vector<uint32_t> &full,
                 const std::vector<uint32_t> &lod, int samples) {
  auto a = soup(p, full), b = soup(p, lod);
  if (a.empty() || b.empty())
    return INFINITY;
  return std::max(oneSided(a, b, samples), oneSided(b, a, samples));
}

} // namespace

LodDistanceMeasure::LodDistanceMeasure(const Character &c, double fps, int samples)
    : c_(c), samples_(samples), diagonal_(restDiagonal(c)), rest_(posedPositions(c, nullptr, 0.0)) {
  for (const auto &clip : c.clips)
    for (double t = clip.start; t <= clip.end + 1e-9; t += 1.0 / fps)
      frames_.push_back(posedPositions(c, &clip, t));
  if (frames_.empty()) // no clips: the rest pose is the one pose drawn
    frames_.push_back(rest_);
}

LodDistance LodDistanceMeasure::measure(const std::vector<uint32_t> &lod) const {
  const auto pct = [&](double d) { return 100.0 * d / diagonal_; };
  LodDistance d;
  d.restPct = pct(hausdorff(rest_, c_.mesh.indices, lod, samples_));
  for (const auto &p : frames_) {
    const double h = pct(hausdorff(p, c_.mesh.indices, lod, samples_));
    d.animatedMaxPct = std::max(d.animatedMaxPct, h);
    d.animatedMeanPct += h / double(frames_.size());
  }
  return d;
}

LodInput loadLodInput(const char *path, Reporter &reporter) {
  LodInput in;
  in.character = importGltf(path, {}, reporter);
  weldExactCopies(in.character.mesh, reporter);
  weldFlatShading(in.character.mesh, reporter);
  in.triangles = lodTriangles(in.character.mesh);
  in.appearance = lodAppearance(in.character.mesh);
  in.poses = samplePoses(in.character, LodOptions{}.poses);
  for (const auto &p : posedPositions(in.character, nullptr, 0.0))
    in.rest.push_back(glm::vec3(p));
  return in;
}

std::vector<uint32_t> lodCut(const LodResult &r, size_t triangles) {
  uint32_t v = uint32_t(r.order.size());
  while (v > r.floorVertices && r.triangleCount[v - 1] >= triangles)
    --v;
  std::vector<uint32_t> out;
  for (uint32_t t = 0; t < r.triangleCount[v]; ++t)
    for (int k = 0; k < 3; ++k) {
      uint32_t i = r.indices[3 * t + uint32_t(k)];
      while (i >= v)
        i = r.collapse[i];
      out.push_back(r.order[i]);
    }
  return out;
}

} // namespace crowd::bench
