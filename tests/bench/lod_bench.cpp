// LOD benchmark: for each input character, our prefix at 50/25/10/5% of the triangles (skinning-
// aware, --poses 16, hard edges closing within the default seam budget as applyLod closes them),
// our pose-agnostic run (--poses 0) and meshopt_simplify at the same triangle
// counts (given the rest pose's positions, as a user would; where one of the three stops above a
// share, all at the highest of their counts), and the full mesh (whose figures are 0 by
// construction: the check on the measure). Ours collapses the rest pose as drawn, as applyLod does.
// Figures: the Hausdorff distance to the full mesh in the rest pose and its maximum and mean over
// every animation frame (30 fps, all clips), as % of the rest pose's bounding-box diagonal
// (lod_distance.h); and the time of our full sequence against meshopt's four calls, in the same
// process.
// With --cuts DIR, gltfpack's own cuts of each asset as well (DIR/ASSET.MODE.SHARE.glb, MODE
// default or permissive: what lod_bench.sh writes with gltfpack -si SHARE [-sp] -noq), measured
// as drawn beside ours cut at the same number of triangles (rows ours_at_gltfpack[_permissive]).
// Usage: lod_bench OUT.csv TIMES.csv [--cuts DIR] FILE.glb...
//        lod_bench --times-only TIMES.csv FILE.glb...   (the times alone: no distances, no grids;
//        what tests/bench/lod_speed.sh runs, alternating with a baseline's lod_bench)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <unordered_map>

#include <sys/resource.h>

#include <meshoptimizer.h>

#include "crowd/bake/import.h"
#include "crowd/bake/lod_bake.h"
#include "crowd/bake/malloc_tuning.h"
#include "lod_distance.h"

namespace {

// The time and memory bound: a 708 x 708 grid, 1,002,528 triangles with no skin (the bind pose
// alone), ours against meshopt's four calls; how far the bake raises the process's peak memory,
// in MB (0 for a grid no larger than one before it). Bumpy, or
// `flat`: there every collapse is free, the case that once went quadratic (PoseQuadrics::key).
void bigMesh(std::ofstream &times, bool flat) {
  const char *name = flat ? "flat_1M" : "grid_1M";
  const float bumps = flat ? 0.0f : 0.02f;
  const int n = 708;
  std::vector<glm::vec3> p;
  std::vector<uint32_t> idx;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x)
      p.push_back({float(x) / n, bumps * std::sin(float(x) * 0.11f) * std::cos(float(y) * 0.07f),
                   float(y) / n});
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const uint32_t a = uint32_t(y * (n + 1) + x), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
      idx.insert(idx.end(), {a, c, b, b, c, d});
    }
  const size_t T = idx.size() / 3;
  crowd::Reporter rep;
  rep.quiet = true;
  rusage before{}, after{};
  getrusage(RUSAGE_SELF, &before);
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const crowd::LodResult r = crowd::bakeLod(p, idx, {}, rep);
  const auto t1 = Clock::now();
  getrusage(RUSAGE_SELF, &after);
  for (double s : {0.5, 0.25, 0.1, 0.05}) {
    std::vector<uint32_t> dst(idx.size());
    meshopt_simplify(dst.data(), idx.data(), idx.size(), &p[0].x, p.size(), sizeof(glm::vec3),
                     size_t(s * double(idx.size())), 1.0f, 0, nullptr);
  }
  const auto t2 = Clock::now();
  auto secs = [](auto d) { return std::chrono::duration<double>(d).count(); };
  times << name << "," << T << ",," << secs(t1 - t0) << "," << secs(t2 - t1) << ",,"
        << double(T) / secs(t1 - t0) / 1e6 << "\n";
  std::printf("%s: %zu triangles to %u at the floor, process peak memory +%.0f MB\n", name, T,
              r.triangleCount[r.floorVertices],
              double(after.ru_maxrss - before.ru_maxrss) / 1024.0);
}

// The fastest of kRepeats runs of `work`, in seconds.
constexpr int kRepeats = 5;
template <class Work> double fastest(Work work) {
  double best = 1e300;
  for (int i = 0; i < kRepeats; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    work();
    best = std::min(best,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}

// The triangles of an outside cut (gltfpack's) on the asset's vertices: each of its vertices is
// the asset's vertex at the same position (meshopt_simplify moves none; -noq keeps the floats),
// else the nearest, counted and said.
std::vector<uint32_t> cutOnAsset(const std::string &file, const std::vector<glm::vec3> &positions,
                                 crowd::Reporter &rep) {
  const crowd::Character cut = crowd::importGltf(file, {}, rep);
  const auto key = [](const glm::vec3 &p) {
    uint32_t w[3];
    std::memcpy(w, &p.x, 12);
    return (uint64_t(w[0]) * 0x9e3779b97f4a7c15ull) ^ (uint64_t(w[1]) * 0xc2b2ae3d27d4eb4full) ^
           w[2];
  };
  std::unordered_multimap<uint64_t, uint32_t> at;
  for (uint32_t v = 0; v < positions.size(); ++v)
    at.emplace(key(positions[v]), v);
  std::vector<uint32_t> asset(cut.mesh.positions.size());
  size_t moved = 0;
  for (size_t v = 0; v < asset.size(); ++v) {
    const glm::vec3 &p = cut.mesh.positions[v];
    bool found = false;
    for (auto [it, end] = at.equal_range(key(p)); it != end && !found; ++it)
      if (positions[it->second] == p)
        asset[v] = it->second, found = true;
    if (found)
      continue;
    ++moved;
    float best = INFINITY;
    for (uint32_t u = 0; u < positions.size(); ++u)
      if (const float d = glm::length(positions[u] - p); d < best)
        best = d, asset[v] = u;
  }
  if (moved)
    std::fprintf(stderr, "%s: %zu of %zu vertices at no vertex of the asset (the nearest taken)\n",
                 file.c_str(), moved, asset.size());
  std::vector<uint32_t> out;
  for (uint32_t i : cut.mesh.indices)
    out.push_back(asset[i]);
  return out;
}

} // namespace

int main(int argc, char **argv) {
  crowd::useHugePages(argv); // the allocator as crowdbake sets it
  crowd::keepFreedMemory();
  const bool timesOnly = argc > 1 && std::string(argv[1]) == "--times-only";
  if (argc < 4) {
    std::fprintf(stderr, "usage: lod_bench OUT.csv TIMES.csv FILE.glb...\n"
                         "       lod_bench --times-only TIMES.csv FILE.glb...\n");
    return 2;
  }
  std::ofstream csv(timesOnly ? "/dev/null" : argv[1]), times(argv[2]);
  int first = 3;
  std::string cuts;
  if (!timesOnly && argc > 4 && std::string(argv[3]) == "--cuts")
    cuts = argv[4], first = 5;
  csv << "asset,method,share,triangles,rest_hausdorff_pct,animated_max_hausdorff_pct,"
         "animated_mean_hausdorff_pct\n";
  times << "asset,triangles,ours_s,ours_bind_only_s,meshopt_4_calls_s,ours_mtris_per_s,"
           "ours_bind_only_mtris_per_s\n";
  for (int f = first; f < argc; ++f) {
    crowd::Reporter rep;
    rep.quiet = true;
    const crowd::bench::LodInput in = crowd::bench::loadLodInput(argv[f], rep);
    std::string asset = std::filesystem::path(argv[f]).stem().string();
    const auto &m = in.character.mesh;
    const size_t T = m.indices.size() / 3;
    const auto &lt = in.triangles;
    const auto &rest = in.rest;
    const auto &app = in.appearance; // hard edges close within the default seam budget
    std::optional<crowd::bench::LodDistanceMeasure> distance; // every frame posed: slow
    if (!timesOnly)
      distance.emplace(in.character);
    // Each timing is the fastest of kRepeats runs (a steady figure, caches warm), in seconds.
    crowd::LodResult ours, agnostic;
    const double oursS = fastest(
        [&] { ours = crowd::bakeLod(rest, lt.indices, {}, rep, lt.group, in.poses, &app); });
    const double agnosticS =
        fastest([&] { agnostic = crowd::bakeLod(rest, lt.indices, {}, rep, lt.group, {}, &app); });
    const double shares[4] = {0.5, 0.25, 0.1, 0.05};
    std::vector<std::vector<uint32_t>> mine, blind, meshopt;
    for (double s : shares) {
      mine.push_back(crowd::bench::lodCut(ours, size_t(std::ceil(s * double(T)))));
      blind.push_back(crowd::bench::lodCut(agnostic, size_t(std::ceil(s * double(T)))));
    }
    const double meshoptS = fastest([&] {
      meshopt.clear();
      for (size_t k = 0; k < 4; ++k) {
        std::vector<uint32_t> dst(m.indices.size());
        size_t n = meshopt_simplify(dst.data(), m.indices.data(), m.indices.size(), &rest[0].x,
                                    rest.size(), sizeof(glm::vec3),
                                    std::max(mine[k].size(), blind[k].size()), 1.0f, 0, nullptr);
        dst.resize(n);
        meshopt.push_back(dst);
      }
    });
    // Each level compares the three at one number of triangles, the highest of their counts:
    // where one stops above the share (its floor), the others are cut at its count too, not a
    // floor compared with a mesh of fewer triangles.
    for (size_t k = 0; k < 4; ++k) {
      const size_t n = std::max({mine[k].size(), blind[k].size(), meshopt[k].size()}) / 3;
      if (mine[k].size() / 3 < n)
        mine[k] = crowd::bench::lodCut(ours, n);
      if (blind[k].size() / 3 < n)
        blind[k] = crowd::bench::lodCut(agnostic, n);
    }
    times << asset << "," << T << "," << oursS << "," << agnosticS << "," << meshoptS << ","
          << double(T) / oursS / 1e6 << "," << double(T) / agnosticS / 1e6 << "\n";
    if (timesOnly)
      continue;

    const auto row = [&](const char *method, double share, const std::vector<uint32_t> &idx) {
      const crowd::bench::LodDistance d = distance->measure(idx);
      csv << asset << "," << method << "," << share << "," << idx.size() / 3 << "," << d.restPct
          << "," << d.animatedMaxPct << "," << d.animatedMeanPct << "\n";
      std::fprintf(stderr, "%s %s %.0f%%: %zu triangles\n", asset.c_str(), method, share * 100,
                   idx.size() / 3);
    };
    row("full", 1.0, m.indices);
    for (size_t k = 0; k < 4; ++k) {
      row("ours", shares[k], mine[k]);
      row("ours_bind_only", shares[k], blind[k]);
      row("meshopt", shares[k], meshopt[k]);
    }
    const char *shareNames[4] = {"0.5", "0.25", "0.1", "0.05"}; // as lod_bench.sh names them
    for (const std::string mode : {"default", "permissive"})
      for (size_t k = 0; k < 4 && !cuts.empty(); ++k) {
        const std::string file = cuts + "/" + asset + "." + mode + "." + shareNames[k] + ".glb";
        if (!std::filesystem::exists(file))
          continue;
        const std::vector<uint32_t> theirs = cutOnAsset(file, in.character.mesh.positions, rep);
        const std::string suffix = mode == "default" ? "" : "_permissive";
        row(("gltfpack" + suffix).c_str(), shares[k], theirs);
        row(("ours_at_gltfpack" + suffix).c_str(), shares[k],
            crowd::bench::lodCut(ours, theirs.size() / 3));
      }
  }
  if (!timesOnly) {
    bigMesh(times, false);
    bigMesh(times, true);
  }
  return 0;
}
