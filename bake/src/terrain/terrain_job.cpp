// The terrain job of an environment build: its one job, the walkable grid of the environment.
#include "crowd/bake/job_inputs.h"
#include "crowd/bake/terrain_bake.h"
#include "crowd/formats/chunks.h"
#include "crowd/formats/terrain.h"

namespace crowd {

using namespace jobs;

Part terrainJob(const Job &job, const std::vector<const Part *> &, const JobContext &context) {
  JobRun run(job, context);
  const CharacterManifest &m = run.m;
  const Character environment = importFile(m, m.body, run.reporter, m.mesh);
  TerrainOptions options = m.terrain.value();
  options.threads = run.threads;
  const TerrainBakeResult r = bakeTerrain(environment, options, run.reporter);
  const pack::Terrain &t = r.terrain;
  Part part;
  part.chunks.push_back({pack::kTerrain, pack::kTerrainVersion, pack::encode(t)});
  part.figures["input_triangles"] = t.indices.size() / 3;
  part.figures["terrain"] = {{"cells", {t.width, t.depth}},
                             {"cell", t.cell},
                             {"walkable_cells", r.walkable},
                             {"blocked_cells", r.blocked},
                             {"unreachable_cells", r.unreachable},
                             {"empty_cells", r.empty},
                             {"walkable_cells_in_shadow", r.walkableInShadow},
                             {"max_shadow_depth", r.maxShadowDepth}};
  run.finish(part);
  return part;
}

} // namespace crowd
