// The embedded executor: runs a plan of jobs on a pool of local workers, each job once its
// dependencies are done, taking parts from the content cache where their keys hit. A failed
// job fails only the jobs that read it. Outcomes are returned in plan order, so what is written
// never depends on scheduling or worker count.
#pragma once
#include <string>
#include <vector>

#include "crowd/bake/content_cache.h"
#include "crowd/bake/job.h"

namespace crowd {

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
};

struct JobOutcome {
  bool cached = false; // the part came from the cache
  bool failed = false;
  std::string error;        // one line, when failed
  std::string cacheProblem; // a damaged entry that was rebuilt
  double seconds = 0;       // bake time (0 when cached)
  Part part;
};

std::vector<JobOutcome> executeJobs(const std::vector<Job> &jobs, const ContentCache &cache,
                                    const ExecutorOptions &options);

} // namespace crowd
