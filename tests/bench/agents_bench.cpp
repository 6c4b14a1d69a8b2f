// The agents' step time: the sample village's terrain (its 80 x 80 m, and
// tiled 2 x 2 for 30k agents), agents spawned over it, every cell wandering, one core (the step
// is sequential by design: agents move in index order). Per crowd: the mean CPU time of a step
// over a simulated minute, against the same crowd looking one cell ahead instead of three (the
// baseline in the same process: what the look-ahead costs), and the share of agent-steps
// blocked by another agent or a wall over that minute.
// Usage: agents_bench [OUT.csv]
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <string>
#include <tuple>

#include "crowd/bake/import.h"
#include "crowd/bake/terrain_bake.h"
#include "crowd/runtime/agents.h"
#include "crowd/samples/samples.h"

using namespace crowd;

namespace {

double cpuSeconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

// `t` repeated n x n times.
pack::Terrain tiled(const pack::Terrain &t, uint32_t n) {
  pack::Terrain out = t;
  out.width = t.width * n, out.depth = t.depth * n;
  out.heights.resize(out.cells());
  out.ground.resize(out.cells());
  out.shadowHeights.resize(out.cells());
  for (uint32_t z = 0; z < out.depth; ++z)
    for (uint32_t x = 0; x < out.width; ++x) {
      const size_t from = t.cellIndex(x % t.width, z % t.depth), to = out.cellIndex(x, z);
      out.heights[to] = t.heights[from];
      out.ground[to] = t.ground[from];
      out.shadowHeights[to] = t.shadowHeights[from];
    }
  return out;
}

struct Run {
  double msPerStep = 0, blockedShare = 0;
  uint32_t moved = 0;
};

Run simulate(const pack::Terrain &t, uint32_t agents, uint32_t lookAhead) {
  runtime::AgentSettings s;
  s.lookAhead = lookAhead;
  runtime::Crowd crowd(t, s);
  std::vector<uint8_t> wander(t.cells() * 4, 0); // green everywhere
  for (size_t i = 0; i < t.cells(); ++i)
    wander[4 * i + 1] = wander[4 * i + 3] = 255;
  crowd.setBehaviours(t.width, t.depth, wander);
  const glm::vec2 lo(t.originX, t.originZ), hi = lo + glm::vec2(t.width, t.depth) * t.cell;
  crowd.spawn({{lo, hi, agents}});
  const uint32_t steps = uint32_t(60 / s.step); // a simulated minute
  const double c0 = cpuSeconds();
  for (uint32_t k = 0; k < steps; ++k)
    crowd.step();
  Run r;
  r.msPerStep = 1e3 * (cpuSeconds() - c0) / steps;
  r.blockedShare = double(crowd.figures().blockedAgentSteps) / (double(steps) * agents);
  r.moved = crowd.figures().spawnedMoved;
  return r;
}

} // namespace

int main(int argc, char **argv) {
  const std::string dir = std::filesystem::temp_directory_path() / "crowd_agents_bench";
  samples::writeSamples(dir);
  Reporter reporter;
  reporter.quiet = true;
  const Character village = importGltf(dir + "/" + samples::kVillageFile, {}, reporter);
  const pack::Terrain small = bakeTerrain(village, {}, reporter).terrain;
  const pack::Terrain large = tiled(small, 2);
  std::FILE *csv = argc > 1 ? std::fopen(argv[1], "w") : nullptr;
  if (csv)
    std::fprintf(csv, "terrain,agents,look_ahead,ms_per_step,baseline_ms,ratio,blocked_share\n");
  std::printf("| terrain | agents | ms a step (look 3) | ms a step (look 1, baseline) | ratio | "
              "blocked agent-steps |\n|---|---|---|---|---|---|\n");
  for (auto [name, terrain, agents] : {std::tuple{"village 80 m", &small, 10000u},
                                       std::tuple{"village 2x2, 160 m", &large, 10000u},
                                       std::tuple{"village 2x2, 160 m", &large, 30000u}}) {
    const Run look = simulate(*terrain, agents, 3), base = simulate(*terrain, agents, 1);
    std::printf("| %s | %u | %.3f | %.3f | %.2f | %.1f%% |\n", name, agents, look.msPerStep,
                base.msPerStep, look.msPerStep / base.msPerStep, 100 * look.blockedShare);
    if (csv)
      std::fprintf(csv, "%s,%u,3,%.4f,%.4f,%.3f,%.4f\n", name, agents, look.msPerStep,
                   base.msPerStep, look.msPerStep / base.msPerStep, look.blockedShare);
  }
  if (csv)
    std::fclose(csv);
  std::printf("one core, CPU time over a simulated minute (1800 steps of 1/30 s)\n");
  return 0;
}
