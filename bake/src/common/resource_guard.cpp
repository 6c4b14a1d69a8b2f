#include "crowd/bake/resource_guard.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <unistd.h>

#include "crowd/formats/container.h"
#include "crowd/formats/error.h"

namespace crowd {

namespace {

uint64_t residentBytes() {
  unsigned long long size = 0, resident = 0;
  if (FILE *f = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(f, "%llu %llu", &size, &resident) != 2)
      resident = 0;
    std::fclose(f);
  }
  return uint64_t(resident) * uint64_t(::sysconf(_SC_PAGESIZE));
}

[[noreturn]] void stopProcess(const std::string &what, const std::string &why,
                              const std::string &kept) {
  pack::abandonPendingWrites();
  std::fprintf(stderr, "crowdbake: error: %s%s%s: stopped, %s\n", what.c_str(),
               what.empty() ? "" : ": ", why.c_str(), kept.c_str());
  std::fflush(stderr);
  std::_Exit(1);
}

} // namespace

void ResourceLimits::validate() const {
  if (!(maxSeconds >= 0 && maxSeconds <= 1e7))
    throw Error("max-seconds: must be in [0, 10000000] (0: no limit)");
  if (maxMemoryMiB > (uint64_t(1) << 30))
    throw Error("max-memory: must be at most 2^30 MiB");
}

uint64_t ResourceLimits::memoryMiB() const {
  if (maxMemoryMiB)
    return maxMemoryMiB;
  const uint64_t physical = uint64_t(::sysconf(_SC_PHYS_PAGES)) * uint64_t(::sysconf(_SC_PAGESIZE));
  return std::max<uint64_t>(1, physical / 4 * 3 >> 20);
}

ResourceGuard::ResourceGuard(const ResourceLimits &limits, std::string what, std::string kept) {
  limits.validate();
  const uint64_t maxBytes = limits.memoryMiB() << 20;
  const double maxSeconds = limits.maxSeconds;
  const auto start = std::chrono::steady_clock::now();
  watchdog_ = std::thread([this, maxBytes, maxSeconds, start, flag = limits.flag,
                           what = std::move(what), kept = std::move(kept)] {
    while (!stop_.load()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      const uint64_t rss = residentBytes();
      if (rss > maxBytes)
        stopProcess(what,
                    "resident memory reached " + std::to_string(rss >> 20) + " MiB, over " + flag +
                        "-memory " + std::to_string(maxBytes >> 20) + " MiB",
                    kept);
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (maxSeconds > 0 && seconds > maxSeconds) {
        char text[96];
        std::snprintf(text, sizeof text, "ran %.2f s, over %s-seconds %g s", seconds, flag.c_str(),
                      maxSeconds);
        stopProcess(what, text, kept);
      }
    }
  });
}

ResourceGuard::~ResourceGuard() {
  stop_ = true;
  watchdog_.join();
}

} // namespace crowd
