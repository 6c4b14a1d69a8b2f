// The content-addressed cache of a library build: job keys (SHA-256 of the baker version, the
// job's kind and canonical settings, its input files' hashes and its dependencies' keys) and a
// folder of parts stored under them. Entries are written atomically, so builds sharing a cache
// (two at once, or a farm's workers on a shared folder) never see torn files; a damaged entry
// fails the container's checksums and is rebuilt.
#pragma once
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "crowd/bake/input_files.h"
#include "crowd/bake/job.h"

namespace crowd {

// Sets every job's key, in plan order (a job's dependencies come before it). Files are hashed
// once each.
void keyJobs(std::vector<Job> &jobs);

class ContentCache {
public:
  explicit ContentCache(std::string folder) : folder_(std::move(folder)) {}
  const std::string &folder() const { return folder_; }
  // An entry's last use is its part file's modification time: load, loadFigures and
  // recordedPack set it to now, so that `crowdbake cache gc` removes the least recently used.
  // The part stored under `key`, or nothing. A damaged entry is reported in `problem` (and
  // left to be overwritten by the rebuilt part).
  std::optional<Part> load(const std::string &key, std::string &problem) const;
  // Writes the part and, beside it, its figures alone (KEY.part.figs, JSON, with the job's kind
  // for `crowdbake cache stats`), so that a warm build reports every job's figures without
  // loading parts no pack needs.
  void store(const std::string &key, const Part &part, const std::string &kind) const;
  // The figures stored with `key` (from the part itself where an older cache has no figures
  // file), or nothing.
  std::optional<nlohmann::ordered_json> loadFigures(const std::string &key) const;
  std::string entryPath(const std::string &key) const;
  // A farm task's failed job, as one line beside where its part would be: the task goes on and
  // the collect step reports it (executor option recordedFailures) instead of running it again.
  void recordFailure(const std::string &key, const std::string &error) const;
  std::optional<std::string> recordedFailure(const std::string &key) const;
  // The hash (hashFile's "sha256:HEX") of the pack written from the link part `key`: a later
  // build whose output file still has it neither loads that part nor writes the pack again.
  void recordPack(const std::string &key, const std::string &hash) const;
  std::optional<std::string> recordedPack(const std::string &key) const;
  // Removes the temporary files that process `pid`, ended mid-write, left beside `key`'s entry.
  void removeTemporaries(const std::string &key, long pid) const;

private:
  void touch(const std::string &key) const;
  std::string folder_;
};

} // namespace crowd
