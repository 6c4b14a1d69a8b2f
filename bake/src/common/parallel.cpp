#include "crowd/bake/parallel.h"

#include <atomic>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace crowd {

int resolveThreads(int threads) {
  if (threads > 0)
    return threads;
  unsigned hw = std::thread::hardware_concurrency();
  return hw ? int(hw) : 1;
}

namespace {

// Helper threads started once and kept: the bakes call parallelFor thousands of times on small
// loops (a clip's bit allotment), where starting threads per call cost more than it shared out.
// One loop at a time uses them; a loop started inside a loop, or beside one on another thread,
// runs on its caller's thread alone (results never depend on the threads).
class HelperPool {
public:
  ~HelperPool() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (auto &t : threads_)
      t.join();
  }

  // Runs `work` on the calling thread and on `helpers` helper threads, and returns when every
  // one of them has returned from it; false (nothing run) where the pool is in use.
  bool run(size_t helpers, const std::function<void()> &work) {
    if (inside_ || !busy_.try_lock())
      return false;
    std::lock_guard busy(busy_, std::adopt_lock);
    {
      std::lock_guard lock(mutex_);
      while (threads_.size() < helpers)
        threads_.emplace_back([this, index = threads_.size()] { serve(index); });
      work_ = &work;
      wanted_ = helpers;
      running_ = helpers;
      ++round_;
    }
    wake_.notify_all();
    inside_ = true;
    work();
    inside_ = false;
    std::unique_lock lock(mutex_);
    finished_.wait(lock, [&] { return running_ == 0; });
    work_ = nullptr;
    return true;
  }

private:
  void serve(size_t index) {
    inside_ = true;
    uint64_t seen = 0;
    std::unique_lock lock(mutex_);
    for (;;) {
      wake_.wait(lock, [&] { return stop_ || round_ != seen; });
      if (stop_)
        return;
      seen = round_;
      if (index >= wanted_)
        continue;
      const std::function<void()> *work = work_;
      lock.unlock();
      (*work)(); // never throws: parallelFor's work catches
      lock.lock();
      if (--running_ == 0)
        finished_.notify_all();
    }
  }

  static thread_local bool inside_; // on a helper, or on the thread running a loop
  std::mutex busy_;                 // held by the loop using the helpers
  std::mutex mutex_;                // guards what follows
  std::condition_variable wake_, finished_;
  std::vector<std::thread> threads_;
  const std::function<void()> *work_ = nullptr;
  size_t wanted_ = 0, running_ = 0;
  uint64_t round_ = 0;
  bool stop_ = false;
};

thread_local bool HelperPool::inside_ = false;

HelperPool &helperPool() {
  static HelperPool pool;
  return pool;
}

} // namespace

void parallelFor(size_t n, int threads, const std::function<void(size_t)> &fn) {
  size_t workers = std::min(size_t(resolveThreads(threads)), n);
  std::atomic<size_t> next{0};
  std::exception_ptr error;
  std::mutex errorMutex;
  const std::function<void()> work = [&] {
    for (size_t i; (i = next.fetch_add(1)) < n;) {
      try {
        fn(i);
      } catch (...) {
        std::lock_guard lock(errorMutex);
        if (!error)
          error = std::current_exception();
        next = n;
      }
    }
  };
  if (workers <= 1 || !helperPool().run(workers - 1, work))
    work();
  if (error)
    std::rethrow_exception(error);
}

} // namespace crowd
