// A bake command (crowdbake anim, lod, outfits, impostor) through the job layer: the command's
// options make a one-character manifest, and one of its jobs runs alone (no cache) as a build
// would run it. Around the job, once for every command: input hashes, progress lines, the
// warnings, provenance, the atomic pack write and the report from the job's figures.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

#include "crowd/bake/manifest.h"

namespace crowd {

struct SingleJobRun {
  std::string command;   // names the bake in provenance and the report
  std::string kind;      // the job to run: "mesh" or "impostor" (its first pair)
  std::string output;    // the pack: PROV and the job's chunks
  bool quiet = false;    // no warnings on stderr
  bool progress = false; // a line per step on stderr
  int threads = 0;
};

// Returns the report: command, inputs, output, baker version, pack bytes, then the job's figures
// (time_s: the whole command, job_s: the job).
nlohmann::ordered_json runSingleJob(const CharacterManifest &character, const SingleJobRun &run);

} // namespace crowd
