// Where a LOD's error comes from: the skinning-aware order (16 poses, as crowdbake lod bakes it)
// and the bind-pose-only order of one character, walked one collapse at a time between two
// triangle counts. Per collapse: the triangles left, the Hausdorff distance to the full mesh at
// rest and its max over every frame (% of the rest pose's diagonal, lod_distance.h), the cost
// the pack stores for it, and how far it moves its vertex in the rest pose (% of the diagonal);
// "<- jump" marks a collapse that raises the rest error by more than 30%. lod_bench gives the
// levels; this says which collapse made one.
// Usage: lod_trace FILE.glb FROM TO   (FROM < TO triangles)
#include <cstdio>
#include <cstdlib>

#include "crowd/bake/lod_bake.h"
#include "lod_distance.h"

namespace {

// The collapses of `r` that leave between `from` and `to` triangles, one line each.
void walk(const char *name, const crowd::LodResult &r, const crowd::bench::LodDistanceMeasure &d,
          size_t from, size_t to) {
  std::printf("%s, one collapse at a time:\n", name);
  double last = -1;
  for (uint32_t v = uint32_t(r.order.size()); v > r.floorVertices; --v) {
    const size_t n = r.triangleCount[v - 1];
    if (n > to || n < from)
      continue;
    const crowd::bench::LodDistance e = d.measure(crowd::bench::lodCut(r, n));
    const uint32_t k = v - 1;
    const double moved = glm::length(d.rest()[r.order[k]] - d.rest()[r.order[r.collapse[k]]]);
    std::printf("  %5zu triangles: rest %7.3f%%  animated max %7.3f%%  cost %9.3g  moved %6.2f%% "
                "(input vertex %u into %u)%s\n",
                n, e.restPct, e.animatedMaxPct, double(r.error[k]), 100 * moved / d.diagonal(),
                r.order[k], r.order[r.collapse[k]],
                last >= 0 && e.restPct > 1.3 * last ? "  <- jump" : "");
    last = e.restPct;
  }
}

} // namespace

int main(int argc, char **argv) {
  if (argc != 4 || std::atoi(argv[2]) <= 0 || std::atoi(argv[2]) >= std::atoi(argv[3])) {
    std::fprintf(stderr, "usage: lod_trace FILE.glb FROM TO   (FROM < TO triangles)\n");
    return 2;
  }
  const size_t from = size_t(std::atoi(argv[2])), to = size_t(std::atoi(argv[3]));
  crowd::Reporter rep;
  rep.quiet = true;
  const crowd::bench::LodInput in = crowd::bench::loadLodInput(argv[1], rep);
  const crowd::bench::LodDistanceMeasure d(in.character);
  const auto &lt = in.triangles;
  const crowd::LodResult ours =
      crowd::bakeLod(in.rest, lt.indices, {}, rep, lt.group, in.poses, &in.appearance);
  const crowd::LodResult bind =
      crowd::bakeLod(in.rest, lt.indices, {}, rep, lt.group, {}, &in.appearance);
  walk("skinning-aware (16 poses)", ours, d, from, to);
  walk("bind pose only", bind, d, from, to);
  return 0;
}
