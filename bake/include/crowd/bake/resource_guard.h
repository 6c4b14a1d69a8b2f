// A resource guard for farms: while alive, a watchdog thread samples the process's resident
// memory and its running time; past either limit it prints one error line naming the limit,
// removes any half-written output (pack::abandonPendingWrites) and ends the process with exit
// code 1, so nothing is written (a library build keeps the packs it wrote before). The limits are
// per command invocation.
#pragma once
#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

namespace crowd {

struct ResourceLimits {
  // Resident memory in MiB (--max-memory). 0: the default, three quarters of physical memory.
  uint64_t maxMemoryMiB = 0;
  // Wall-clock seconds (--max-seconds); 0: no limit (a library build's default: its jobs have
  // limits of their own).
  double maxSeconds = 3600;
  // How the error line names the limits: "--max" (a command's own) or "--job-max" (a job's).
  std::string flag = "--max";
  void validate() const;
  uint64_t memoryMiB() const; // the effective memory limit
};

class ResourceGuard {
public:
  // `what` names the work in the error line ("crowdbake anim soldier.glb"; "": the line says
  // only what limit it passed); `kept` says what stopping leaves behind.
  ResourceGuard(const ResourceLimits &limits, std::string what,
                std::string kept = "nothing written");
  ~ResourceGuard();
  ResourceGuard(const ResourceGuard &) = delete;
  ResourceGuard &operator=(const ResourceGuard &) = delete;

private:
  std::atomic<bool> stop_{false};
  std::thread watchdog_;
};

} // namespace crowd
