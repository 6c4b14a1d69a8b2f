#include "crowd/bake/build.h"

#include <chrono>
#include <filesystem>
#include <sys/resource.h>
#include <unistd.h>

#include "crowd/bake/cache_admin.h"
#include "crowd/bake/manifest.h"
#include "crowd/bake/provenance.h"
#include "crowd/formats/container.h"
#include "crowd/formats/error.h"

namespace crowd {

namespace fs = std::filesystem;
using nlohmann::ordered_json;

size_t BuildResult::failed() const {
  size_t n = 0;
  for (const auto &c : characters)
    n += c.failed;
  return n;
}

BuildPlan planBuild(const BuildOptions &o) {
  BuildPlan plan;
  plan.library = loadLibrary(o.input, o.files);
  const Library &lib = plan.library;
  std::string &cacheFolder = plan.cache;
  cacheFolder = o.cache;
  if (lib.single && fs::path(o.output).extension() != ".crowdpack")
    throw Error(o.output + ": a character manifest builds one pack: -o NAME.crowdpack");
  if (!lib.single) {
    std::error_code ec;
    fs::create_directories(o.output, ec);
    if (ec || !fs::is_directory(o.output))
      throw Error(o.output + ": cannot create the output folder" +
                  (ec ? ": " + ec.message() : std::string()));
  }
  if (cacheFolder.empty())
    cacheFolder = lib.single ? (fs::path(o.output).parent_path() / ".crowdbake-cache").string()
                             : (fs::path(o.output) / ".cache").string();

  auto planJobs = [](const Library &library, std::vector<Job> &jobs,
                     std::vector<std::pair<size_t, size_t>> &ranges) {
    for (const auto &m : library.characters) {
      auto more = planCharacter(std::make_shared<CharacterManifest>(m), jobs.size());
      ranges.emplace_back(jobs.size(), jobs.size() + more.size() - 1);
      jobs.insert(jobs.end(), more.begin(), more.end());
    }
    keyJobs(jobs);
  };
  if (!o.scene.scene.empty()) {
    std::vector<std::pair<size_t, size_t>> fullRanges;
    planJobs(lib, plan.fullJobs, fullRanges);
    plan.scene = narrowToScene(plan.library, o.scene, o.files);
  }
  planJobs(lib, plan.jobs, plan.ranges);
  for (const auto &m : lib.characters)
    plan.packs.push_back(lib.single ? o.output
                                    : (fs::path(o.output) / (m.name + ".crowdpack")).string());
  plan.upToDate.assign(lib.characters.size(), 0);
  return plan;
}

void findUpToDatePacks(BuildPlan &plan) {
  const ContentCache cache(plan.cache);
  for (size_t c = 0; c < plan.packs.size(); ++c) {
    const auto recorded = cache.recordedPack(plan.jobs[plan.ranges[c].second].key);
    std::error_code ec;
    plan.upToDate[c] = recorded && fs::is_regular_file(plan.packs[c], ec) &&
                       hashFile(plan.packs[c]).hash == *recorded;
  }
}

namespace {

// How a child process finds job `job` of the plan again (job_process.h).
JobSpec jobSpec(const BuildOptions &o, const BuildPlan &plan, size_t job, int threads) {
  size_t c = 0;
  while (plan.ranges[c].second < job)
    ++c;
  const CharacterManifest &m = plan.library.characters[c];
  JobSpec s;
  s.library = plan.library.path;
  s.entry = m.entry;
  s.job = job - plan.ranges[c].first;
  s.key = plan.jobs[job].key;
  s.cache = plan.cache;
  s.threads = threads;
  s.files = o.files;
  s.scene = o.scene;
  s.limits = m.limits.over(o.jobLimits);
  s.parent = ::getpid();
  return s;
}

} // namespace

BuildResult build(const BuildOptions &o) {
  const auto t0 = std::chrono::steady_clock::now();
  BuildPlan plan = planBuild(o);
  const CacheLease lease(plan.cache); // before the cache is read: a gc keeps what it uses
  findUpToDatePacks(plan);
  ExecutorOptions executor = o.executor;
  executor.written.assign(plan.jobs.size(), 0);
  for (size_t c = 0; c < plan.ranges.size(); ++c)
    executor.written[plan.ranges[c].second] = plan.upToDate[c];
  if (!o.jobExecutable.empty())
    executor.runApart = [&](size_t i, int threads) {
      return runJobProcess(o.jobExecutable, jobSpec(o, plan, i, threads));
    };
  std::vector<PackWrite> writes(plan.packs.size());
  std::vector<size_t> linkOf(plan.jobs.size(), plan.packs.size()); // job -> its character's pack
  for (size_t c = 0; c < plan.ranges.size(); ++c)
    linkOf[plan.ranges[c].second] = c;
  executor.finished = [&](size_t i, JobOutcome &out) {
    const size_t c = linkOf[i];
    if (c == plan.packs.size() || plan.upToDate[c])
      return;
    writes[c] = writePack(plan, c, out.part);
    out.part.chunks = {}; // written: its figures stay for the report
  };
  const auto outcomes = executeJobs(plan.jobs, ContentCache(plan.cache), executor);
  BuildResult r =
      finishBuild(o, plan, outcomes, writes,
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  if (!lease.problem().empty())
    r.report["cache_lease"] = lease.problem();
  // Peak resident memory: this process's (the plan, the parts of the packs being written, the
  // report) and the largest job's (a child process; 0 when every job ran here).
  rusage self{}, children{};
  getrusage(RUSAGE_SELF, &self);
  getrusage(RUSAGE_CHILDREN, &children);
  r.report["peak_memory_mib"] = {{"build", self.ru_maxrss / 1024},
                                 {"largest_job", children.ru_maxrss / 1024}};
  return r;
}

namespace {

// What a scene build saved against the full library: bake seconds (as each part recorded when
// it ran) and pack bytes, summed over the jobs of each from the cache, where it holds them all.
ordered_json sceneSavings(const BuildPlan &plan) {
  const ContentCache cache(plan.cache);
  struct Totals {
    double seconds = 0;
    uint64_t bytes = 0;
    size_t missing = 0;
  };
  auto totals = [&](const std::vector<Job> &jobs) {
    Totals t;
    for (const Job &job : jobs) {
      if (auto figures = cache.loadFigures(job.key)) {
        t.seconds += figures->value("time_s", 0.0);
        t.bytes += figures->value("pack_bytes", uint64_t(0));
      } else {
        ++t.missing;
      }
    }
    return t;
  };
  const Totals full = totals(plan.fullJobs), scene = totals(plan.jobs);
  ordered_json j{{"jobs", plan.jobs.size()}, {"full_build_jobs", plan.fullJobs.size()}};
  if (full.missing + scene.missing > 0) {
    j["saved"] = std::to_string(full.missing + scene.missing) + " of the " +
                 std::to_string(plan.fullJobs.size() + plan.jobs.size()) +
                 " parts of the full and the scene build are not in the cache: build the whole "
                 "library into the same cache once to measure what the scene saves";
    return j;
  }
  j["full_build"] = {{"bake_s", full.seconds}, {"pack_bytes", full.bytes}};
  j["scene_build"] = {{"bake_s", scene.seconds}, {"pack_bytes", scene.bytes}};
  j["saved"] = {{"bake_s", full.seconds - scene.seconds},
                {"pack_bytes", int64_t(full.bytes) - int64_t(scene.bytes)}};
  return j;
}

} // namespace

PackWrite writePack(const BuildPlan &plan, size_t c, const Part &link) {
  PackWrite w;
  try {
    const auto bytes = characterPackBytes(link);
    pack::writeFileAtomic(plan.packs[c], bytes);
    w.bytes = bytes.size();
    ContentCache(plan.cache)
        .recordPack(plan.jobs[plan.ranges[c].second].key, hashFile(plan.packs[c]).hash);
    w.written = true;
  } catch (const std::exception &e) {
    w.error = e.what();
  }
  return w;
}

BuildResult finishBuild(const BuildOptions &o, const BuildPlan &plan,
                        const std::vector<JobOutcome> &outcomes,
                        const std::vector<PackWrite> &writes, double seconds) {
  const Library &lib = plan.library;
  const auto &jobs = plan.jobs;
  const auto &ranges = plan.ranges;
  BuildResult result;
  ordered_json &r = result.report;
  r["baker_version"] = kBakerVersion;
  r["input"] = o.input;
  r["output"] = o.output;
  r["cache"] = plan.cache;
  // The summary first (set below): at a thousand characters the report is tens of MB.
  for (const char *key :
       {"jobs", "characters_failed", "failed_characters", "interrupted", "time_s"})
    r[key] = nullptr;
  r["failed_characters"] = ordered_json::array();
  size_t run = 0, cached = 0, failed = 0;
  for (size_t c = 0; c < lib.characters.size(); ++c) {
    CharacterBuild cb;
    cb.name = lib.characters[c].name;
    ordered_json cj;
    cj["name"] = cb.name;
    for (size_t i = ranges[c].first; i <= ranges[c].second; ++i) {
      const auto &out = outcomes[i];
      ++cb.jobs;
      cb.run += !out.cached && !out.failed;
      cb.cached += out.cached;
      cb.failedJobs += out.failed;
      cb.seconds += out.seconds;
      if (out.failed && cb.error.empty())
        cb.error = jobs[i].label() + ": " + out.error;
      ordered_json jj{{"kind", jobs[i].kind}, {"label", jobs[i].label()}, {"key", jobs[i].key},
                      {"cached", out.cached}, {"failed", out.failed},     {"seconds", out.seconds}};
      if (out.failed)
        jj["error"] = out.error;
      if (!out.cacheProblem.empty())
        jj["damaged_cache_entry"] = out.cacheProblem;
      if (!out.retried.empty())
        jj["retried_after"] = out.retried;
      result.interrupted = result.interrupted || out.interrupted;
      if (!out.failed)
        jj["figures"] = out.part.figures;
      cj["jobs"].push_back(jj);
    }
    cb.failed = cb.failedJobs > 0;
    if (!cb.failed && plan.upToDate[c]) {
      cb.pack = plan.packs[c];
      cb.bytes = fs::file_size(cb.pack);
    } else if (!cb.failed && writes[c].written) {
      cb.pack = plan.packs[c];
      cb.bytes = writes[c].bytes;
    } else if (!cb.failed) {
      cb.failed = true;
      cb.error = writes[c].error.empty() ? plan.packs[c] + ": not written" : writes[c].error;
    }
    run += cb.run, cached += cb.cached, failed += cb.failedJobs;
    cj["status"] = cb.failed ? "failed" : "ok";
    if (cb.failed)
      r["failed_characters"].push_back(cb.name);
    if (cb.failed)
      cj["error"] = cb.error;
    cj["pack"] = cb.pack;
    cj["pack_bytes"] = cb.bytes;
    cj["pack_up_to_date"] = !cb.failed && plan.upToDate[c]; // neither loaded nor written
    cj["jobs_run"] = cb.run;
    cj["jobs_cached"] = cb.cached;
    cj["jobs_failed"] = cb.failedJobs;
    cj["bake_s"] = cb.seconds;
    r["characters"].push_back(cj);
    result.characters.push_back(cb);
  }
  r["jobs"] = {{"total", jobs.size()}, {"run", run}, {"cached", cached}, {"failed", failed}};
  r["characters_failed"] = result.failed();
  r["interrupted"] = result.interrupted;
  r["time_s"] = seconds;
  if (!o.scene.scene.empty()) {
    r["scene"] = plan.scene;
    r["scene"].update(sceneSavings(plan));
  }
  return result;
}

} // namespace crowd
