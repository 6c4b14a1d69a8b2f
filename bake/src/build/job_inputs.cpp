#include "crowd/bake/job_inputs.h"

#include <algorithm>

#include "crowd/bake/import.h"
#include "crowd/formats/error.h"

namespace crowd::jobs {
namespace {

// Keeps only the manifest's clips, in the manifest's order; an unknown name is an error that
// lists the file's clips.
void keepClips(Character &c, const std::vector<std::string> &names, const std::string &file) {
  if (names.empty())
    return;
  std::vector<AnimationClip> kept;
  for (const auto &name : names) {
    auto it = std::find_if(c.clips.begin(), c.clips.end(), [&](auto &k) { return k.name == name; });
    if (it == c.clips.end())
      throw Error(file + ": " + unknownName("clip", name, c.clipNames()).what());
    kept.push_back(*it);
  }
  c.clips = std::move(kept);
}

} // namespace

double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

JobRun::JobRun(const Job &job, const JobContext &context)
    : m(*job.character), threads(context.threads) {
  reporter.quiet = true;
  reporter.onStep = context.progress;
}

void JobRun::finish(Part &part) const {
  auto list = nlohmann::ordered_json::array();
  for (const auto &w : reporter.warnings())
    list.push_back({{"code", w.code}, {"message", w.message}, {"count", w.count}});
  part.figures["time_s"] = since(t0);
  part.figures["warnings"] = std::move(list);
}

Character importFile(const CharacterManifest &m, const std::string &file, Reporter &reporter,
                     const std::string &mesh) {
  ImportOptions io;
  io.input = m.input;
  io.mesh = mesh;
  return importGltf(file, io, reporter);
}

Character importBody(const CharacterManifest &m, Reporter &reporter) {
  Character body = importFile(m, m.body, reporter, m.mesh);
  keepClips(body, m.clips, m.body);
  return body;
}

std::string outfitFile(const CharacterManifest &m, const std::string &outfit) {
  for (const auto &[name, file] : m.outfits)
    if (name == outfit)
      return file;
  throw Error("character '" + m.name + "': no outfit named '" + outfit + "'");
}

} // namespace crowd::jobs
