// The cloth job of a character build: one garment's loop found in its cloth cache.
#include "crowd/bake/bake_figures.h"
#include "crowd/bake/cloth_bake.h"
#include "crowd/bake/job_inputs.h"
#include "crowd/formats/chunks.h"
#include "crowd/formats/cloth.h"

namespace crowd {

using namespace jobs;

Part clothJob(const Job &job, const std::vector<const Part *> &, const JobContext &context) {
  JobRun run(job, context);
  const CharacterManifest &m = run.m;
  const ClothEntry &e = m.cloth.at(job.cloth);
  const Character body = importBody(m, run.reporter);
  const Character outfit = importFile(m, outfitFile(m, e.outfit), run.reporter);
  ClothBakeOptions opt = e.options;
  opt.loop.search.threads = opt.loop.edges.threads = run.threads;
  const ClothBakeResult r =
      bakeClothLoop(body, outfit, e.outfit, e.garment, e.clip, e.cache, m.input, opt, run.reporter);
  Part part;
  part.chunks.push_back({pack::kCloth, pack::kClothVersion, pack::encode(r.chunk)});
  part.figures = clothFigures(r);
  run.finish(part);
  return part;
}

} // namespace crowd
