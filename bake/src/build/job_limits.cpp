// A job's limits checked (a manifest's reader needs this alone).
#include "crowd/bake/job_limits.h"

#include <string>

#include "crowd/formats/error.h"

namespace crowd {

void JobLimits::validate() const {
  if (!(maxSeconds >= 0 && maxSeconds <= kMostSeconds))
    throw Error("job-max-seconds: must be in [0, " + std::to_string(int64_t(kMostSeconds)) +
                "] (0: no limit)");
  if (maxMemoryMiB > kMostMemoryMiB)
    throw Error("job-max-memory: must be at most 2^30 MiB (0: no limit)");
}

} // namespace crowd
