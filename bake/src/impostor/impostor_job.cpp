// The impostor job of a character build: one (clip, outfit) pair's atlas, and where the manifest
// asks, its accuracy against the mesh drawn.
#include "crowd/bake/bake_figures.h"
#include "crowd/bake/impostor_bake.h"
#include "crowd/bake/job_inputs.h"
#include "crowd/bake/outfit_bake.h"
#include "crowd/formats/chunks.h"
#include "crowd/formats/impostor.h"

namespace crowd {

using namespace jobs;

Part impostorJob(const Job &job, const std::vector<const Part *> &, const JobContext &context) {
  JobRun run(job, context);
  const CharacterManifest &m = run.m;
  Character c = importBody(m, run.reporter);
  uint32_t garments = 0;
  if (!job.outfit.empty()) {
    OutfitInput o{job.outfit, importFile(m, outfitFile(m, job.outfit), run.reporter), {}};
    garments = uint32_t(o.character.mesh.parts.size());
    c = dressCharacter(c, o, m.outfitOptions.regions, run.reporter);
  }
  ImpostorOptions opt = m.impostor;
  opt.clip = job.clip;
  opt.threads = run.threads;
  ImpostorBakeResult r = bakeImpostor(c, opt, run.reporter);
  r.impostor.outfit = job.outfit;
  Part part;
  part.chunks.push_back({pack::kImpostor, pack::kImpostorVersion, pack::encode(r.impostor)});
  auto &f = part.figures;
  f = impostorFigures(r, opt);
  f["outfit"] = job.outfit;
  f["body_regions"] = uint32_t(c.mesh.parts.size()) - garments;
  f["garment_regions"] = garments;
  if (opt.measure) {
    run.reporter.step("impostor accuracy: views against the mesh drawn");
    const auto t1 = Clock::now();
    f["accuracy"] = impostorAccuracyFigures(measureImpostor(c, r.impostor, run.threads));
    f["accuracy"]["time_s"] = since(t1);
  }
  run.finish(part);
  return part;
}

} // namespace crowd
