// LOD benchmark: for each input character, our prefix at 50/25/10/5% of the triangles (skinning-
// aware, --poses 16), our pose-agnostic run (--poses 0) and meshopt_simplify at the same triangle
// counts: symmetric Hausdorff distance to the full mesh in the bind pose and its maximum over
// every animation frame (30 fps, all clips), as % of the bind-pose bounding-box diagonal; and the
// time of our full sequence against meshopt's four calls, in the same process.
// Hausdorff: points sampled on each mesh (every vertex, plus area-uniform samples from a fixed
// seed) against a CGAL AABB tree of the other's triangles, both ways; the same estimate as CGAL's
// approximate_Hausdorff_distance, but over triangle soups, which LOD cuts and meshopt's output
// may be (non-manifold), where a Surface_mesh could not be built.
// Usage: lod_bench OUT.csv TIMES.csv FILE.glb...
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>
#include <meshoptimizer.h>

#include "crowd/bake/evaluate.h"
#include "crowd/bake/import.h"
#include "crowd/bake/lod_bake.h"

namespace {

using K = CGAL::Simple_cartesian<double>;
using Triangle = K::Triangle_3;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_triangle_primitive<
                                                     K, std::vector<Triangle>::const_iterator>>>;

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
                 const std::vector<uint32_t> &lod) {
  auto a = soup(p, full), b = soup(p, lod);
  if (a.empty() || b.empty())
    return INFINITY;
  return std::max(oneSided(a, b, 4000), oneSided(b, a, 4000));
}

// Our cut at the fewest vertices holding `triangles`, as indices into the input vertices.
std::vector<uint32_t> cut(const crowd::LodResult &r, size_t triangles) {
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

} // namespace

int main(int argc, char **argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: lod_bench OUT.csv TIMES.csv FILE.glb...\n");
    return 2;
  }
  std::ofstream csv(argv[1]), times(argv[2]);
  csv << "asset,method,share,triangles,bind_hausdorff_pct,animated_max_hausdorff_pct\n";
  times << "asset,triangles,ours_s,ours_bind_only_s,meshopt_4_calls_s,ours_mtris_per_s\n";
  for (int f = 3; f < argc; ++f) {
    crowd::Reporter rep;
    rep.quiet = true;
    crowd::Character c = crowd::importGltf(argv[f], {}, rep);
    std::string asset = std::filesystem::path(argv[f]).stem().string();
    const auto &m = c.mesh;
    const size_t T = m.indices.size() / 3;
    const auto group = crowd::subMeshGroups(m);
    const auto poses = crowd::samplePoses(c, crowd::LodOptions{}.poses); // as crowdbake lod does
    using Clock = std::chrono::steady_clock;
    auto t0 = Clock::now();
    crowd::LodResult ours = crowd::bakeLod(m.positions, m.indices, {}, rep, group, poses);
    auto t1 = Clock::now();
    crowd::LodResult agnostic = crowd::bakeLod(m.positions, m.indices, {}, rep, group, {});
    auto t2 = Clock::now();
    const double shares[4] = {0.5, 0.25, 0.1, 0.05};
    std::vector<std::vector<uint32_t>> mine, blind, meshopt;
    for (double s : shares) {
      mine.push_back(cut(ours, size_t(std::ceil(s * double(T)))));
      blind.push_back(cut(agnostic, size_t(std::ceil(s * double(T)))));
    }
    auto t3 = Clock::now();
    for (size_t k = 0; k < 4; ++k) {
      std::vector<uint32_t> dst(m.indices.size());
      size_t n = meshopt_simplify(dst.data(), m.indices.data(), m.indices.size(),
                                  &m.positions[0].x, m.positions.size(), sizeof(glm::vec3),
                                  mine[k].size(), 1.0f, 0, nullptr);
      dst.resize(n);
      meshopt.push_back(dst);
    }
    auto t4 = Clock::now();
    auto secs = [](auto d) { return std::chrono::duration<double>(d).count(); };
    times << asset << "," << T << "," << secs(t1 - t0) << "," << secs(t2 - t1) << ","
          << secs(t4 - t3) << "," << double(T) / secs(t1 - t0) / 1e6 << "\n";

    glm::dvec3 lo(INFINITY), hi(-INFINITY);
    std::vector<glm::dvec3> bind;
    for (auto p : m.positions) {
      bind.push_back(glm::dvec3(p));
      lo = glm::min(lo, glm::dvec3(p));
      hi = glm::max(hi, glm::dvec3(p));
    }
    const double diag = glm::length(hi - lo);
    std::vector<std::vector<glm::dvec3>> frames; // every clip at 30 fps
    for (const auto &clip : c.clips)
      for (double t = clip.start; t <= clip.end + 1e-9; t += 1.0 / 30)
        frames.push_back(crowd::posedPositions(c, &clip, t));
    const char *names[3] = {"ours", "ours_bind_only", "meshopt"};
    for (int method = 0; method < 3; ++method)
      for (size_t k = 0; k < 4; ++k) {
        const auto &idx = method == 0 ? mine[k] : method == 1 ? blind[k] : meshopt[k];
        double animated = 0;
        for (const auto &p : frames)
          animated = std::max(animated, hausdorff(p, m.indices, idx));
        csv << asset << "," << names[method] << "," << shares[k] << "," << idx.size() / 3 << ","
            << 100 * hausdorff(bind, m.indices, idx) / diag << "," << 100 * animated / diag
            << "\n";
        std::fprintf(stderr, "%s %s %.0f%%: %zu triangles\n", asset.c_str(), names[method],
                     shares[k] * 100, idx.size() / 3);
      }
  }
  return 0;
}
