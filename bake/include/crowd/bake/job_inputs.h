// What every job function (registered in job.cpp's jobKinds, each in its bake's folder) starts
// from: its frame (JobRun), and the manifest's files imported under its input policy.
#pragma once
#include <chrono>
#include <string>

#include <nlohmann/json.hpp>

#include "crowd/bake/character.h"
#include "crowd/bake/job.h"
#include "crowd/bake/manifest.h"
#include "crowd/bake/report.h"

namespace crowd::jobs {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0); // seconds

// A job function's frame: what it starts with (its manifest, thread count, clock, and a
// reporter whose warnings go to the part's figures, its steps to the context's progress) and the
// figures it ends with.
struct JobRun {
  JobRun(const Job &job, const JobContext &context);
  // The part's last figures: "time_s" since the start, and "warnings".
  void finish(Part &part) const;

  const CharacterManifest &m;
  const int threads;
  const Clock::time_point t0 = Clock::now();
  Reporter reporter;
};

// A file of the manifest (its body or an outfit), read under the manifest's input policy; `mesh`
// picks one mesh of the file by name.
Character importFile(const CharacterManifest &m, const std::string &file, Reporter &reporter,
                     const std::string &mesh = "");
// The manifest's body, with only its clips, in its order (an unknown name lists the file's).
Character importBody(const CharacterManifest &m, Reporter &reporter);
// The file of the manifest's outfit `outfit`.
std::string outfitFile(const CharacterManifest &m, const std::string &outfit);

} // namespace crowd::jobs
