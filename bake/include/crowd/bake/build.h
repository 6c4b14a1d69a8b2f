// crowdbake build: a character manifest into one character pack, or a library of them into a
// folder of packs, through the job plan, the content cache and an executor. A character whose
// job fails is reported and left out; the others are written.
#pragma once
#include "crowd/bake/input_files.h"
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "crowd/bake/executor.h"
#include "crowd/bake/manifest.h"
#include "crowd/bake/scene_build.h"

namespace crowd {

struct BuildOptions {
  std::string input;  // CHARACTER.json or LIBRARY.json
  std::string output; // OUT.crowdpack for one character; a folder for a library
  std::string cache;  // default: OUTDIR/.cache (one character: beside OUT, .crowdbake-cache)
  std::string report; // build report JSON; default: OUTDIR/build.report.json (library only)
  ExecutorOptions executor;
  InputPolicy files;       // where manifests' and glTFs' files may resolve, and their size bound
  SceneBuildOptions scene; // --scene: only what one scene draws
};

struct CharacterBuild {
  std::string name, pack; // pack: the file written ("" when it failed)
  bool failed = false;
  std::string error; // the first failing job's one-line error
  size_t jobs = 0, run = 0, cached = 0, failedJobs = 0;
  double seconds = 0; // bake time summed over its jobs
  uint64_t bytes = 0;
};

struct BuildResult {
  std::vector<CharacterBuild> characters;
  nlohmann::ordered_json report;
  size_t failed() const;
};

BuildResult build(const BuildOptions &options);

// The steps of build(), which a farm runs apart (slurm.h): the jobs of every character, keyed,
// and where the cache is; then the packs and the report from the jobs' outcomes.
struct BuildPlan {
  Library library;
  std::vector<Job> jobs;
  std::vector<std::pair<size_t, size_t>> ranges; // per character: its jobs [first, last]
  std::string cache;
  std::vector<std::string> packs; // per character: the pack it writes
  // Per character: its pack already holds what its link job would write, so it is neither
  // loaded nor written (all 0 until findUpToDatePacks).
  std::vector<char> upToDate;
  // --scene: the report's account of what was left out, and the jobs of the full library (to
  // measure against, from the cache).
  nlohmann::ordered_json scene;
  std::vector<Job> fullJobs;
};
BuildPlan planBuild(const BuildOptions &options);
// Marks the characters whose pack file has the hash the cache recorded for their link's key.
void findUpToDatePacks(BuildPlan &plan);
BuildResult finishBuild(const BuildOptions &options, const BuildPlan &plan,
                        const std::vector<JobOutcome> &outcomes, double seconds);

} // namespace crowd
