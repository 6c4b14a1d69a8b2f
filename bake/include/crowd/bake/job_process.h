// A library build's jobs, each in a child process of its own (this same crowdbake, run as
// `crowdbake build-job SPEC`), so that a job that runs past its limits, crashes or is killed
// fails alone and the others go on. The spec names the job, not its data: the child loads its
// character's manifest again (one entry of the library, narrowed as a scene build narrowed it),
// plans it, checks that the job's key is the one the parent planned, reads its dependencies'
// parts from the cache (baking one again where the cache no longer holds it), and stores its
// part in the cache, where the parent reads it back.
//
// Limits: the child's resource guard stops it past --job-max-memory (its own resident memory);
// the parent kills it at --job-max-seconds. On Slurm the same limits are the tasks' --time and
// --mem (slurm.h).
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "crowd/bake/input_files.h"
#include "crowd/bake/job.h"
#include "crowd/bake/job_limits.h"
#include "crowd/bake/scene_build.h"

namespace crowd {

class ContentCache;

struct JobSpec {
  std::string library;     // the character manifest or library the build read
  size_t entry = 0;        // the character's entry in it (CharacterManifest::entry)
  size_t job = 0;          // the job's index among its character's jobs (planCharacter)
  std::string key;         // the key the parent planned for it
  std::string cache;       // the content cache folder
  int threads = 1;         // the job's worker threads
  InputPolicy files;       // where the inputs may resolve and their size bound
  SceneBuildOptions scene; // a scene build: the child narrows the character the same way
  JobLimits limits;
  long parent = 0;          // the build's pid: a job whose build has ended does not start
  std::string text() const; // JSON, the child's one argument
  static JobSpec parse(const std::string &text); // throws naming the bad field
};

struct JobProcessOutcome {
  bool ok = false;
  // Ended by a signal that no limit of ours sent (a SIGKILL from outside, the OOM killer): the
  // executor runs such a job once more.
  bool killedFromOutside = false;
  bool interrupted = false; // stopped by an interrupt of the build (interruptRequested)
  std::string error;        // one line, when not ok
};

// In the parent: runs the spec's job in `executable` and waits for it, killing it at its
// --job-max-seconds or at an interrupt; the error is the child's own error line, or what ended it.
JobProcessOutcome runJobProcess(const std::string &executable, const JobSpec &spec);

// In the child (crowdbake build-job): runs the spec's job under its limits into the cache. It
// ends with its build: killed when the build's process ends (a build stopped by its own
// --max-seconds, or killed) rather than left baking for no one.
void runJobSpec(const JobSpec &spec);
// The jobs of the spec's character, keyed, as the build planned them (a Slurm task's too).
// Throws when the job's key is not the spec's: its inputs changed since the build was planned.
std::vector<Job> planJobsOf(const JobSpec &spec);
// Job `job` of one character's keyed `jobs` baked with `threads` and stored in `cache`: its
// dependencies' parts read from the cache, any that left it (a cache gc) baked again first.
Part bakeIntoCache(const std::vector<Job> &jobs, size_t job, const ContentCache &cache,
                   int threads);

// SIGINT and SIGTERM during a build: the first asks the build to stop (no job starts after it,
// running children are stopped, what finished stays in the cache); a second ends the process.
void catchInterrupts();
bool interruptRequested();

} // namespace crowd
