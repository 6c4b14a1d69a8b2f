#include "crowd/bake/executor.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>

#include "crowd/bake/parallel.h"

namespace crowd {

namespace {

using Clock = std::chrono::steady_clock;

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

} // namespace

std::vector<JobOutcome> executeJobs(const std::vector<Job> &jobs, const ContentCache &cache,
                                    const ExecutorOptions &options) {
  const size_t n = jobs.size();
  std::vector<JobOutcome> out(n);
  std::vector<size_t> waiting(n);
  std::vector<std::vector<size_t>> readers(n);
  std::deque<size_t> ready;
  for (size_t i = 0; i < n; ++i) {
    waiting[i] = jobs[i].deps.size();
    for (size_t d : jobs[i].deps)
      readers[d].push_back(i);
    if (waiting[i] == 0)
      ready.push_back(i);
  }
  // Readers first: a job whose part is in the cache needs none of its dependencies, so a warm
  // build loads only the parts that the packs are written from.
  std::vector<char> settled(n, 0);
  for (size_t i = n; i-- > 0;) {
    bool needed = readers[i].empty() && !(i < options.written.size() && options.written[i]);
    for (size_t r : readers[i])
      needed = needed || !out[r].cached; // r will run
    if (!needed) {
      out[i].cached = true; // not loaded: no reader needs it; its figures are for the report
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
  const int workers =
      std::max(1, std::min(resolveThreads(options.workers), int(std::max<size_t>(n, 1))));
  // A job's threads are the cores shared among the jobs that run beside it when it starts: the
  // ones running and the ones ready to (at most `workers`). A job that starts alone, as a
  // character's mesh job after its cloth jobs often does, gets every core.
  const int cores = resolveThreads(0);
  int running = 0;
  std::mutex mutex;
  std::condition_variable wake;
  size_t finished = 0, cachedCount = 0, failedCount = 0;
  double bakeSeconds = 0; // summed over baked jobs, for the ETA
  size_t baked = 0;
  const auto start = Clock::now();

  auto report = [&](size_t i) { // under the lock
    const JobOutcome &o = out[i];
    if (options.progress == "lines") {
      std::string what = o.failed   ? "FAILED: " + o.error
                         : o.cached ? "cached"
                                    : std::to_string(o.seconds).substr(0, 5) + " s";
      std::fprintf(stderr, "crowdbake: [%zu/%zu] %s: %s\n", finished, n, jobs[i].label().c_str(),
                   what.c_str());
    } else if (options.progress == "bar") {
      const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
      const double perJob = baked ? bakeSeconds / double(baked) : 0;
      const double eta = perJob * double(n - finished) / workers;
      std::fprintf(stderr, "\r\033[K[%zu/%zu] %zu cached, %zu failed, %s elapsed%s  %s", finished,
                   n, cachedCount, failedCount, duration(elapsed).c_str(),
                   baked ? (", ETA " + duration(eta)).c_str() : "", jobs[i].label().c_str());
      if (finished == n)
        std::fprintf(stderr, "\n");
    }
    if (!o.cacheProblem.empty() && options.progress != "none")
      std::fprintf(stderr, "%scrowdbake: warning: damaged cache entry rebuilt: %s\n",
                   options.progress == "bar" ? "\n" : "", o.cacheProblem.c_str());
  };

  // Marks i done and releases (or, on failure, fails) the jobs that read it. Under the lock.
  std::function<void(size_t)> done = [&](size_t i) {
    ++finished;
    cachedCount += out[i].cached;
    failedCount += out[i].failed;
    report(i);
    for (size_t r : readers[i]) {
      if (out[i].failed && !out[r].failed) {
        out[r].failed = true;
        out[r].error = "not run: " + jobs[i].label() + " failed";
      }
      if (--waiting[r] == 0) {
        if (out[r].failed)
          done(r);
        else
          ready.push_back(r);
      }
    }
    wake.notify_all();
  };

  auto work = [&] {
    std::unique_lock lock(mutex);
    while (finished < n) {
      if (ready.empty()) {
        wake.wait(lock);
        continue;
      }
      const size_t i = ready.front();
      ready.pop_front();
      ++running;
      const int beside = std::min(workers, running + int(ready.size()));
      const int threads = std::max(1, cores / beside);
      std::vector<const Part *> deps;
      for (size_t d : jobs[i].deps)
        deps.push_back(&out[d].part);
      lock.unlock();
      JobOutcome o;
      o.cacheProblem = out[i].cacheProblem;
      try {
        if (settled[i]) {
          o = std::move(out[i]);
        } else {
          const auto t0 = Clock::now();
          o.part = runJob(jobs[i], deps, {threads, {}});
          o.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
          cache.store(jobs[i].key, o.part);
        }
      } catch (const std::bad_alloc &) {
        o.failed = true;
        o.error = "out of memory";
      } catch (const std::exception &e) {
        o.failed = true;
        o.error = oneLine(e.what());
      }
      lock.lock();
      --running;
      out[i] = std::move(o);
      if (!out[i].cached && !out[i].failed) {
        bakeSeconds += out[i].seconds;
        ++baked;
      }
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
