#include "crowd/bake/cache_admin.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <ctime>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

#include "crowd/formats/error.h"

namespace crowd {

namespace fs = std::filesystem;
using nlohmann::ordered_json;

namespace {

constexpr double kTemporaryAge = 3600; // seconds: older temporaries' writers are gone
constexpr double kClockSlack = 2;      // seconds: file times' granularity on shared file systems

double now() {
  timespec t{};
  clock_gettime(CLOCK_REALTIME, &t);
  return double(t.tv_sec) + t.tv_nsec * 1e-9;
}

double modified(const fs::path &p) {
  struct stat s {};
  if (::stat(p.c_str(), &s) != 0)
    return 0;
  return double(s.st_mtim.tv_sec) + s.st_mtim.tv_nsec * 1e-9;
}

// One key's files: its part, figures, recorded pack hash and recorded failure.
struct Entry {
  std::vector<fs::path> files;
  uint64_t bytes = 0;
  double lastUse = 0; // the part file's time (ContentCache::touch)
  bool part = false, failure = false;
};

struct Scan {
  std::map<std::string, Entry> entries;
  std::vector<std::pair<fs::path, double>> temporaries; // with their ages
  uint64_t temporaryBytes = 0;
};

Scan scan(const std::string &folder) {
  Scan s;
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw Error(folder + ": not a cache folder");
  const double t = now();
  for (const auto &dir : fs::directory_iterator(folder, ec)) {
    const std::string d = dir.path().filename().string();
    if (d.size() != 2 || !dir.is_directory())
      continue; // leases/, and anything not the cache's
    for (const auto &f : fs::directory_iterator(dir.path(), ec)) {
      const std::string name = f.path().filename().string();
      const uint64_t size = f.is_regular_file(ec) ? f.file_size(ec) : 0;
      if (name.find(".tmp-") != std::string::npos) {
        s.temporaries.emplace_back(f.path(), t - modified(f.path()));
        s.temporaryBytes += size;
        continue;
      }
      const size_t dot = name.find('.');
      if (dot == std::string::npos || name.compare(dot, 5, ".part") != 0)
        continue;
      Entry &e = s.entries[name.substr(0, dot)];
      e.files.push_back(f.path());
      e.bytes += size;
      if (name.size() == dot + 5) {
        e.part = true;
        e.lastUse = modified(f.path());
      }
      e.failure = e.failure || name.ends_with(".failed");
    }
  }
  for (auto &[key, e] : s.entries)
    if (!e.part) // a recorded failure alone: its own time
      for (const auto &f : e.files)
        e.lastUse = std::max(e.lastUse, modified(f));
  return s;
}

std::string kindOf(const Entry &e) {
  for (const auto &f : e.files)
    if (f.string().ends_with(".part.figs")) {
      std::ifstream in(f);
      const auto j = ordered_json::parse(in, nullptr, false);
      if (j.is_object() && j.contains("job_kind") && j["job_kind"].is_string())
        return j["job_kind"];
    }
  return "unknown";
}

// The start times of the builds holding a lease now; removes the leases of ended ones.
std::vector<double> liveLeases(const std::string &folder, size_t &stale) {
  std::vector<double> starts;
  std::error_code ec;
  for (const auto &f : fs::directory_iterator(fs::path(folder) / "leases", ec)) {
    if (f.path().extension() != ".lease")
      continue;
    const int fd = ::open(f.path().c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0)
      continue;
    if (::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK) {
      char text[64] = {};
      const ssize_t n = ::pread(fd, text, sizeof text - 1, 0);
      starts.push_back(n > 0 ? std::atof(text) : 0); // unreadable: protect everything
    } else {
      fs::remove(f.path(), ec);
      ++stale;
    }
    ::close(fd);
  }
  return starts;
}

std::string iso(double t) {
  if (t <= 0)
    return "";
  const time_t s = time_t(t);
  tm utc{};
  gmtime_r(&s, &utc);
  char b[32];
  std::strftime(b, sizeof b, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return b;
}

} // namespace

CacheLease::CacheLease(const std::string &cacheFolder) {
  std::error_code ec;
  const fs::path dir = fs::path(cacheFolder) / "leases";
  fs::create_directories(dir, ec);
  static std::atomic<int> serial{0};
  const std::string name = std::to_string(::getpid()) + "-" + std::to_string(serial++);
  // Locked and written under another name first: a gc never sees an unlocked lease of a build.
  const std::string draft = (dir / (name + ".draft")).string();
  path_ = (dir / (name + ".lease")).string();
  fd_ = ::open(draft.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  char text[64];
  const int n = std::snprintf(text, sizeof text, "%.3f\n", now());
  if (fd_ < 0 || ::flock(fd_, LOCK_EX) != 0 || ::write(fd_, text, size_t(n)) != n ||
      ::rename(draft.c_str(), path_.c_str()) != 0) {
    problem_ = cacheFolder + ": cannot hold a lease in the cache (" + std::strerror(errno) +
               "): a gc now may remove parts this build uses, which it then bakes again";
    fs::remove(draft, ec);
    path_.clear();
  }
}

CacheLease::~CacheLease() {
  std::error_code ec;
  if (!path_.empty())
    fs::remove(path_, ec);
  if (fd_ >= 0)
    ::close(fd_);
}

CacheStats cacheStats(const std::string &folder) {
  const Scan s = scan(folder);
  CacheStats st;
  for (const auto &[key, e] : s.entries) {
    st.bytes += e.bytes;
    st.failures += e.failure;
    if (!e.part)
      continue;
    ++st.entries;
    auto &k = st.kinds[kindOf(e)];
    ++k.entries;
    k.bytes += e.bytes;
    st.oldestUse = st.oldestUse == 0 ? e.lastUse : std::min(st.oldestUse, e.lastUse);
    st.newestUse = std::max(st.newestUse, e.lastUse);
  }
  st.temporaries = s.temporaries.size();
  st.bytes += s.temporaryBytes;
  size_t stale = 0;
  st.liveBuilds = liveLeases(folder, stale).size();
  return st;
}

ordered_json CacheStats::json() const {
  ordered_json j{{"entries", entries}, {"bytes", bytes}, {"by_kind", ordered_json::object()}};
  for (const auto &[name, k] : kinds)
    j["by_kind"][name] = {{"entries", k.entries}, {"bytes", k.bytes}};
  j["recorded_failures"] = failures;
  j["temporary_files"] = temporaries;
  j["live_builds"] = liveBuilds;
  j["oldest_use"] = iso(oldestUse);
  j["newest_use"] = iso(newestUse);
  return j;
}

GcResult collectGarbage(const std::string &folder, uint64_t maxBytes) {
  GcResult r;
  const std::vector<double> starts = liveLeases(folder, r.staleLeases);
  // Scanned after the leases: an entry a build touches from now on is newer than its lease.
  Scan s = scan(folder);
  const double keepFrom =
      starts.empty() ? INFINITY : *std::min_element(starts.begin(), starts.end()) - kClockSlack;
  std::error_code ec;
  for (const auto &[path, age] : s.temporaries)
    if (age > kTemporaryAge && fs::remove(path, ec))
      ++r.temporaries;
  std::vector<std::pair<double, const std::string *>> byUse;
  uint64_t total = 0;
  for (const auto &[key, e] : s.entries) {
    byUse.emplace_back(e.lastUse, &key);
    total += e.bytes;
  }
  std::sort(byUse.begin(), byUse.end());
  for (const auto &[lastUse, key] : byUse) {
    const Entry &e = s.entries[*key];
    // Used since the scan (a build that began after the leases were read): kept too.
    const bool usedSince =
        e.part && modified(e.files.front().parent_path() / (*key + ".part")) > lastUse;
    if (total <= maxBytes || lastUse >= keepFrom || usedSince) {
      r.inUse += total > maxBytes;
      ++r.kept;
      r.keptBytes += e.bytes;
      continue;
    }
    // The part last: a reader that finds it finds its figures too, or goes without them.
    std::vector<fs::path> files = e.files;
    std::stable_partition(files.begin(), files.end(),
                          [](const fs::path &f) { return !f.string().ends_with(".part"); });
    for (const auto &f : files)
      fs::remove(f, ec);
    total -= e.bytes;
    ++r.removed;
    r.removedBytes += e.bytes;
  }
  return r;
}

ordered_json GcResult::json() const {
  return {{"removed", removed},
          {"removed_bytes", removedBytes},
          {"kept", kept},
          {"kept_bytes", keptBytes},
          {"kept_in_use", inUse},
          {"temporary_files_removed", temporaries},
          {"stale_leases_removed", staleLeases}};
}

uint64_t parseSize(const std::string &text) {
  size_t used = 0;
  double value = -1;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception &) {
  }
  const std::string unit = text.substr(std::min(used, text.size()));
  const std::map<std::string, double> units = {
      {"", 1}, {"K", 0x1p10}, {"M", 0x1p20}, {"G", 0x1p30}, {"T", 0x1p40}};
  const auto it = units.find(unit);
  if (!(value >= 0) || it == units.end() || !std::isfinite(value * it->second) ||
      value * it->second >= 0x1p63)
    throw Error("'" + text + "' is not a size (bytes, or a number with K, M, G or T)");
  return uint64_t(value * it->second);
}

} // namespace crowd
