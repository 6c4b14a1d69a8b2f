#include "crowd/bake/single_job.h"

#include <chrono>
#include <cstdio>
#include <memory>

#include "crowd/bake/content_cache.h"
#include "crowd/bake/job.h"
#include "crowd/bake/provenance.h"
#include "crowd/formats/container.h"
#include "crowd/formats/error.h"

namespace crowd {

using nlohmann::ordered_json;

ordered_json runSingleJob(const CharacterManifest &character, const SingleJobRun &run) {
  const auto t0 = std::chrono::steady_clock::now();
  auto say = [&](const std::string &line) {
    if (run.progress)
      std::fprintf(stderr, "crowdbake: %s\n", line.c_str());
  };
  std::vector<Job> jobs;
  for (auto &j : planCharacter(std::make_shared<CharacterManifest>(character), 0))
    if (j.kind == run.kind && jobs.empty())
      jobs.push_back(std::move(j));
  if (jobs.empty())
    throw Error("no " + run.kind + " job for " + character.body);
  jobs[0].deps.clear(); // a mesh or impostor job reads no other part
  keyJobs(jobs);
  const Job &job = jobs[0];
  say("baking " + job.label() + " from " + character.body);
  const Part part =
      runJob(job, {}, {run.threads, run.progress ? Reporter::Listener(say) : nullptr});
  for (const auto &w : part.figures.value("warnings", ordered_json::array()))
    if (!run.quiet)
      std::fprintf(stderr, "crowdbake: warning: %s\n", w.value("message", "").c_str());

  Part out;
  out.chunks.push_back(provenanceChunk(job, run.command));
  out.chunks.insert(out.chunks.end(), part.chunks.begin(), part.chunks.end());
  const std::vector<uint8_t> bytes = characterPackBytes(out);
  pack::writeFileAtomic(run.output, bytes);

  ordered_json r;
  r["command"] = run.command;
  r["input"] = character.body;
  for (const auto &[name, file] : character.outfits)
    r["outfit_files"].push_back({{"name", name}, {"file", file}});
  r["output"] = run.output;
  r["baker_version"] = kBakerVersion;
  r["pack_bytes"] = bytes.size();
  r.update(part.figures);
  r["job_s"] = part.figures.value("time_s", 0.0);
  r["time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  say("wrote " + run.output + " (" + std::to_string(bytes.size()) + " bytes)");
  return r;
}

} // namespace crowd
