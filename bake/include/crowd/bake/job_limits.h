// Bounds on one job of a library build, enforced on the child process that runs it
// (job_process.h): a job past either fails alone and the others go on. Not a setting: a limit
// changes no byte of a part, so it stays out of job keys and provenance.
#pragma once
#include <cstdint>

namespace crowd {

struct JobLimits {
  double maxSeconds = 0;     // wall clock: --job-max-seconds, a manifest's "limits": {"seconds"}
  uint64_t maxMemoryMiB = 0; // resident memory: --job-max-memory, "limits": {"memory_mib"}
  // 0 is no bound; these are the largest a user may ask for (the build's own --max-* bound the
  // parent process, not its jobs).
  static constexpr double kMostSeconds = 1e7;
  static constexpr uint64_t kMostMemoryMiB = uint64_t(1) << 30;
  void validate() const; // throws naming the limit
  // Each bound this one sets, else the default's (a character's manifest over the command line).
  JobLimits over(const JobLimits &defaults) const {
    return {maxSeconds > 0 ? maxSeconds : defaults.maxSeconds,
            maxMemoryMiB > 0 ? maxMemoryMiB : defaults.maxMemoryMiB};
  }
};

} // namespace crowd
