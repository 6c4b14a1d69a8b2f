#include "crowd/bake/executor.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <functional>
#include <mutex>
#include <thread>

#include "crowd/bake/parallel.h"

namespace crowd {

namespace {

using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

std::string oneLine(std::string s) {
  for (char &c : s)
    if (c == '\n')
      c = ' ';
  return s;
}

std::string duration(double s) {
  char b[32];
  if (s < 60)
    std::snprintf(b, sizeof b, "%.0fs", s);
  else
    std::snprintf(b, sizeof b, "%dm%02ds", int(s) / 60, int(s) % 60);
  return b;
}

double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

JobOutcome runHere(const Job &job, const std::vector<const Part *> &deps, int threads,
                   const ContentCache &cache) {
  JobOutcome o;
  try {
    const auto t0 = Clock::now();
    o.part = runJob(job, deps, {threads, {}});
    o.seconds = since(t0);
    cache.store(job.key, o.part, job.kind);
  } catch (const std::bad_alloc &) {
    o.failed = true;
    o.error = "out of memory";
  } catch (const std::exception &e) {
    o.failed = true;
    o.error = oneLine(e.what());
  }
  return o;
}

// Job i in a child process, then from the cache what this process needs of its part: all of
// it for a pack (`whole`), else the figures for the report.
JobOutcome runApart(size_t i, const Job &job, bool whole, int threads, const ContentCache &cache,
                    const ExecutorOptions &options) {
  // A job whose process cannot start (no executable, no process left to fork) fails alone.
  auto start = [&] {
    try {
      return options.runApart(i, threads);
    } catch (const std::exception &e) {
      return JobProcessOutcome{false, false, false, e.what()};
    }
  };
  JobOutcome o;
  const auto t0 = Clock::now();
  JobProcessOutcome r = start();
  if (!r.ok && r.killedFromOutside && !interruptRequested()) {
    o.retried = oneLine(r.error);
    r = start();
  }
  o.seconds = since(t0);
  o.interrupted = r.interrupted;
  std::string problem;
  if (!r.ok) {
    o.failed = true;
    o.error = oneLine(r.error) + (o.retried.empty() ? "" : " (ran twice: first " + o.retried + ")");
  } else if (!whole) {
    if (auto figures = cache.loadFigures(job.key))
      o.part.figures = std::move(*figures);
  } else if (auto part = cache.load(job.key, problem)) {
    o.part = std::move(*part);
  } else {
    o.failed = true;
    o.error = "its part is not in the cache after it ran" + (problem.empty() ? "" : ": " + problem);
  }
  return o;
}

// Who reads each job's part, how many of its dependencies each still waits for, and the jobs
// that wait for none.
struct JobGraph {
  std::vector<size_t> waiting;
  std::vector<std::vector<size_t>> readers;
  std::deque<size_t> ready;
  explicit JobGraph(const std::vector<Job> &jobs) : waiting(jobs.size()), readers(jobs.size()) {
    for (size_t i = 0; i < jobs.size(); ++i) {
      waiting[i] = jobs[i].deps.size();
      for (size_t d : jobs[i].deps)
        readers[d].push_back(i);
      if (waiting[i] == 0)
        ready.push_back(i);
    }
  }
};

// The outcomes the cache gives before any job runs (a part, a recorded failure), readers first:
// a job whose part is in the cache needs none of its dependencies, and a job baked in a child
// process reads its dependencies there, so a warm build loads only the parts that the packs are
// written from. Returns which jobs are settled.
std::vector<char> settleFromCache(const std::vector<Job> &jobs, const JobGraph &graph,
                                  const ContentCache &cache, const ExecutorOptions &options,
                                  std::vector<JobOutcome> &out) {
  std::vector<char> settled(jobs.size(), 0);
  for (size_t i = jobs.size(); i-- > 0;) {
    const auto &readers = graph.readers[i];
    const bool forPack = readers.empty() && !(i < options.written.size() && options.written[i]);
    bool readerRuns = false;
    for (size_t r : readers)
      readerRuns = readerRuns || !out[r].cached;
    // Not loaded: no reader needs it, or those that run read it in processes of their own. Its
    // figures are for the report.
    if (!forPack &&
        (!readerRuns || (options.runApart && fs::exists(cache.entryPath(jobs[i].key))))) {
      out[i].cached = true;
      settled[i] = 1;
      if (auto figures = cache.loadFigures(jobs[i].key))
        out[i].part.figures = std::move(*figures);
      continue;
    }
    if (auto hit = cache.load(jobs[i].key, out[i].cacheProblem)) {
      out[i].cached = true;
      settled[i] = 1;
      out[i].part = std::move(*hit);
    } else if (auto error =
                   options.recordedFailures ? cache.recordedFailure(jobs[i].key) : std::nullopt) {
      out[i].failed = true;
      out[i].error = oneLine(*error);
      settled[i] = 1;
    }
    out[i].cacheProblem = oneLine(out[i].cacheProblem);
  }
  return settled;
}

// The build's progress on stderr (ExecutorOptions::progress): a line per job, or one bar with
// counts and an ETA from the mean time of the jobs baked so far.
class Progress {
public:
  Progress(const std::vector<Job> &jobs, const ExecutorOptions &options, int workers)
      : jobs_(jobs), mode_(options.progress), workers_(workers) {}

  void finished(size_t i, const JobOutcome &o) { // under the executor's lock
    ++finished_;
    cached_ += o.cached;
    failed_ += o.failed;
    if (!o.cached && !o.failed) {
      bakeSeconds_ += o.seconds;
      ++baked_;
    }
    const size_t n = jobs_.size();
    if (mode_ == "lines") {
      std::string what = o.failed   ? "FAILED: " + o.error
                         : o.cached ? "cached"
                                    : std::to_string(o.seconds).substr(0, 5) + " s";
      std::fprintf(stderr, "crowdbake: [%zu/%zu] %s: %s\n", finished_, n, jobs_[i].label().c_str(),
                   what.c_str());
    } else if (mode_ == "bar") {
      const double perJob = baked_ ? bakeSeconds_ / double(baked_) : 0;
      const double eta = perJob * double(n - finished_) / workers_;
      std::fprintf(stderr, "\r\033[K[%zu/%zu] %zu cached, %zu failed, %s elapsed%s  %s", finished_,
                   n, cached_, failed_, duration(since(start_)).c_str(),
                   baked_ ? (", ETA " + duration(eta)).c_str() : "", jobs_[i].label().c_str());
      if (finished_ == n)
        std::fprintf(stderr, "\n");
    }
    if (!o.cacheProblem.empty() && mode_ != "none")
      std::fprintf(stderr, "%scrowdbake: warning: damaged cache entry rebuilt: %s\n",
                   mode_ == "bar" ? "\n" : "", o.cacheProblem.c_str());
  }
  size_t count() const { return finished_; }

private:
  const std::vector<Job> &jobs_;
  const std::string mode_;
  const int workers_;
  const Clock::time_point start_ = Clock::now();
  size_t finished_ = 0, cached_ = 0, failed_ = 0, baked_ = 0;
  double bakeSeconds_ = 0; // summed over baked jobs, for the ETA
};

} // namespace

std::string dependencyFailed(const Job &dependency) {
  return "not run: " + dependency.label() + " failed";
}

std::vector<JobOutcome> executeJobs(const std::vector<Job> &jobs, const ContentCache &cache,
                                    const ExecutorOptions &options) {
  const size_t n = jobs.size();
  std::vector<JobOutcome> out(n);
  JobGraph graph(jobs);
  const std::vector<char> settled = settleFromCache(jobs, graph, cache, options, out);
  const int workers =
      std::max(1, std::min(resolveThreads(options.workers), int(std::max<size_t>(n, 1))));
  // A job's threads are the cores shared among the jobs that run beside it when it starts: the
  // ones running and the ones ready to (at most `workers`). A job that starts alone, as a
  // character's mesh job after its cloth jobs often does, gets every core.
  const int cores = resolveThreads(0);
  int running = 0;
  std::mutex mutex;
  std::condition_variable wake;
  Progress progress(jobs, options, workers);

  // Marks i done and releases (or, on failure, fails) the jobs that read it. Under the lock.
  std::function<void(size_t)> done = [&](size_t i) {
    progress.finished(i, out[i]);
    for (size_t r : graph.readers[i]) {
      if (out[i].failed && !out[r].failed) {
        out[r].failed = true;
        out[r].error = dependencyFailed(jobs[i]);
        out[r].interrupted = out[i].interrupted;
      }
      if (--graph.waiting[r] == 0) {
        if (out[r].failed)
          done(r);
        else
          graph.ready.push_back(r);
      }
    }
    wake.notify_all();
  };

  auto work = [&] {
    std::unique_lock lock(mutex);
    while (progress.count() < n) {
      if (graph.ready.empty()) {
        wake.wait(lock);
        continue;
      }
      const size_t i = graph.ready.front();
      graph.ready.pop_front();
      ++running;
      const int beside = std::min(workers, running + int(graph.ready.size()));
      const int threads = std::max(1, cores / beside);
      std::vector<const Part *> deps;
      for (size_t d : jobs[i].deps)
        deps.push_back(&out[d].part);
      lock.unlock();
      JobOutcome o;
      if (settled[i]) {
        o = std::move(out[i]);
      } else if (interruptRequested()) {
        o.failed = o.interrupted = true;
        o.error = "interrupted before it started";
      } else if (options.runApart) {
        o = runApart(i, jobs[i], graph.readers[i].empty(), threads, cache, options);
      } else {
        o = runHere(jobs[i], deps, threads, cache);
      }
      if (!settled[i])
        o.cacheProblem = std::move(out[i].cacheProblem);
      if (options.finished && !o.failed)
        options.finished(i, o);
      lock.lock();
      --running;
      out[i] = std::move(o);
      done(i);
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < workers; ++t)
    pool.emplace_back(work);
  work();
  for (auto &t : pool)
    t.join();
  return out;
}

} // namespace crowd
