// The child's side of job_process.h: crowdbake build-job SPEC.
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <sys/prctl.h>
#include <thread>
#include <unistd.h>

#include "crowd/bake/content_cache.h"
#include "crowd/bake/job_process.h"
#include "crowd/bake/resource_guard.h"
#include "crowd/formats/error.h"

namespace crowd {

// Its one entry of the library, narrowed to the scene in a scene build.
std::vector<Job> planJobsOf(const JobSpec &spec) {
  Library library = loadLibrary(spec.library, spec.files, spec.entry);
  if (!spec.scene.scene.empty())
    narrowToScene(library, spec.scene, spec.files);
  if (library.characters.empty())
    throw Error(spec.library + ": entry " + std::to_string(spec.entry) +
                " is not in the build any more");
  std::vector<Job> jobs =
      planCharacter(std::make_shared<CharacterManifest>(library.characters[0]), 0);
  keyJobs(jobs);
  if (spec.job >= jobs.size() || jobs[spec.job].key != spec.key)
    throw Error(library.characters[0].name +
                ": its inputs changed since the build was planned: build again");
  return jobs;
}

Part bakeIntoCache(const std::vector<Job> &jobs, size_t job, const ContentCache &cache,
                   int threads) {
  // A dependency's part comes from the cache; one that left it since the build looked (a
  // cache gc) is baked again here.
  std::function<Part(size_t)> partOf = [&](size_t i) {
    std::string problem;
    if (i != job)
      if (auto part = cache.load(jobs[i].key, problem))
        return std::move(*part);
    std::vector<Part> deps;
    for (size_t d : jobs[i].deps)
      deps.push_back(partOf(d));
    std::vector<const Part *> depParts;
    for (const auto &d : deps)
      depParts.push_back(&d);
    Part part = runJob(jobs[i], depParts, {threads, {}});
    cache.store(jobs[i].key, part, jobs[i].kind);
    return part;
  };
  return partOf(job);
}

namespace {

// A test's hold on jobs (docs/farm.md): with CROWD_JOB_HOLD=DIR each job writes its pid to
// DIR/ENTRY.JOB.pid as it starts, and one that finds DIR/ENTRY.JOB.hold takes it (renamed to
// .held, so a retry runs on) and waits until that file is removed or the job is killed. Tests of
// limits, kills and interrupts then act on events, never on how long a bake takes.
void holdForTest(const JobSpec &spec) {
  const char *dir = std::getenv("CROWD_JOB_HOLD");
  if (!dir || !*dir)
    return;
  namespace fs = std::filesystem;
  const fs::path base =
      fs::path(dir) / (std::to_string(spec.entry) + "." + std::to_string(spec.job));
  const fs::path pid = base.string() + ".pid", held = base.string() + ".held";
  std::ofstream(pid.string() + ".tmp") << ::getpid() << "\n";
  std::error_code ec;
  fs::rename(pid.string() + ".tmp", pid, ec); // whole or absent to a reader
  fs::rename(base.string() + ".hold", held, ec);
  if (ec)
    return; // not held
  while (fs::exists(held))
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
}

} // namespace

void runJobSpec(const JobSpec &spec) {
  // The spawning thread of the build lives until its jobs end, so its death is the build's.
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (spec.parent != 0 && ::getppid() != spec.parent)
    throw Error("the build that started this job has ended");
  holdForTest(spec);
  ResourceLimits guardLimits;
  guardLimits.flag = "--job-max";
  guardLimits.maxMemoryMiB = spec.limits.maxMemoryMiB;
  guardLimits.maxSeconds = 0; // none: the parent keeps the time limit
  ResourceGuard guard(guardLimits, "");
  bakeIntoCache(planJobsOf(spec), spec.job, ContentCache(spec.cache), spec.threads);
}

} // namespace crowd
