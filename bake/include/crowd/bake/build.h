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
  // Runs each job in a child process of this executable (crowdbake build: job_process.h), under
  // its character's limits over `jobLimits`; "": every job in this process, unbounded.
  std::string jobExecutable;
  JobLimits jobLimits; // --job-max-seconds, --job-max-memory
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
  bool interrupted = false; // SIGINT or SIGTERM stopped it: what finished is in the cache
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
// A character's pack, written as soon as its link job ends (so that a build holds the parts of
// the packs being written, not of every pack): its bytes, or why it could not be written.
struct PackWrite {
  bool written = false;
  uint64_t bytes = 0;
  std::string error;
};
PackWrite writePack(const BuildPlan &plan, size_t character, const Part &link);
BuildResult finishBuild(const BuildOptions &options, const BuildPlan &plan,
                        const std::vector<JobOutcome> &outcomes,
                        const std::vector<PackWrite> &writes, double seconds);

} // namespace crowd
