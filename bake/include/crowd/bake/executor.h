// The embedded executor: runs a plan of jobs on a pool of local workers, each job once its
// dependencies are done, taking parts from the content cache where their keys hit. A failed
// job fails only the jobs that read it. After an interrupt (job_process.h) no job starts. Outcomes
// are returned in plan order, so what is written never depends on scheduling or worker count.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "crowd/bake/content_cache.h"
#include "crowd/bake/job.h"
#include "crowd/bake/job_process.h"

namespace crowd {

struct JobOutcome {
  bool cached = false; // the part came from the cache
  bool failed = false;
  std::string error;        // one line, when failed
  std::string cacheProblem; // a damaged entry that was rebuilt
  bool interrupted = false; // failed because the build was interrupted (interruptRequested)
  std::string retried;      // the first run's error, when a job killed from outside ran again
  double seconds = 0;       // bake time (0 when cached)
  Part part;
};

// The error of a job not run because `dependency`, a job it reads, failed (locally or on a
// farm task).
std::string dependencyFailed(const Job &dependency);

struct ExecutorOptions {
  int workers = 0; // jobs run at once (0: all cores); each gets the cores shared among the
                   // jobs running or ready when it starts
  // Progress on stderr: "bar" redraws one line with counts and ETA (a terminal), "lines" prints
  // a line per finished job, "none" prints nothing.
  std::string progress = "lines";
  // A job with no part in the cache but a failure recorded there by a farm task fails with
  // that error instead of running (the collect step of a Slurm build).
  bool recordedFailures = false;
  // Per job (empty: none): its output is already written, so no one needs its part; it counts
  // as cached and is neither run nor loaded (a link whose pack is up to date).
  std::vector<char> written;
  // Runs job i with `threads` in a child process that leaves its part in the cache (a library
  // build: job_process.h). A job killed from outside runs once more. Empty: jobs run in this
  // process.
  std::function<JobProcessOutcome(size_t job, int threads)> runApart;
  // Called by the worker as each job ends (not failed), before its readers start: a build
  // writes a link's pack here and keeps only its figures.
  std::function<void(size_t job, JobOutcome &outcome)> finished;
};

std::vector<JobOutcome> executeJobs(const std::vector<Job> &jobs, const ContentCache &cache,
                                    const ExecutorOptions &options);

} // namespace crowd
