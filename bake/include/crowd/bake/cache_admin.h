// The content cache at scale: what it holds (crowdbake cache stats) and trimming it to a size,
// least recently used first (crowdbake cache gc), while other builds read and write it.
//
// Safety: every build holds a lease in the cache (CACHE/leases/, an flock held for the build's
// life). gc never removes an entry used since the oldest live lease began; anything older that
// a build still wanted is baked again by that build (job_process.h), never read torn: a file is
// only ever replaced by a rename or removed whole.
#pragma once
#include <cstdint>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

namespace crowd {

// Held by a build (or a Slurm task) while it uses the cache. One that cannot be held (a full
// disk, a read-only share) says why in problem() and the build goes on without it.
class CacheLease {
public:
  explicit CacheLease(const std::string &cacheFolder);
  const std::string &problem() const { return problem_; }
  ~CacheLease();
  CacheLease(const CacheLease &) = delete;
  CacheLease &operator=(const CacheLease &) = delete;

private:
  std::string path_, problem_;
  int fd_ = -1;
};

struct CacheStats {
  struct Kind {
    size_t entries = 0;
    uint64_t bytes = 0;
  };
  size_t entries = 0;                  // parts (a part, its figures, its recorded pack hash)
  uint64_t bytes = 0;                  // every file of the cache
  std::map<std::string, Kind> kinds;   // by job kind ("unknown": stored before kinds were)
  size_t failures = 0;                 // failures recorded by farm tasks
  size_t temporaries = 0;              // files a writer that was killed left behind
  size_t liveBuilds = 0;               // builds holding a lease now
  double oldestUse = 0, newestUse = 0; // seconds since the epoch; 0 when empty
  nlohmann::ordered_json json() const;
};
CacheStats cacheStats(const std::string &folder);

struct GcResult {
  size_t removed = 0, kept = 0;
  uint64_t removedBytes = 0, keptBytes = 0;
  size_t inUse = 0; // entries over the size kept because a live build may use them
  size_t temporaries = 0, staleLeases = 0;
  nlohmann::ordered_json json() const;
};
// Removes least recently used entries until the cache holds at most `maxBytes`, but none used
// since the oldest live build began; also temporary files older than an hour and the leases of
// builds that ended without removing theirs.
GcResult collectGarbage(const std::string &folder, uint64_t maxBytes);

// "500M", "2G", "1.5T", "1048576": bytes; throws crowd::Error naming the text.
uint64_t parseSize(const std::string &text);

} // namespace crowd
