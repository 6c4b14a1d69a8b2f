// parallelFor keeps its helper threads between loops: every index runs once, a loop inside a
// loop and loops on two threads at once finish (each on its own where the helpers are taken),
// and the first error of a loop reaches its caller.
#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "crowd/bake/parallel.h"

using namespace crowd;

namespace {

TEST(Parallel, EveryIndexRunsOnceLoopAfterLoop) {
  for (size_t n : {0u, 1u, 2u, 7u, 1000u})
    for (int threads : {1, 2, 4}) {
      std::vector<std::atomic<int>> runs(n);
      parallelFor(n, threads, [&](size_t i) { runs[i]++; });
      for (size_t i = 0; i < n; ++i)
        EXPECT_EQ(runs[i].load(), 1) << n << " on " << threads;
    }
}

TEST(Parallel, ALoopInsideALoopFinishes) {
  std::atomic<size_t> total{0};
  parallelFor(8, 4, [&](size_t) { parallelFor(100, 4, [&](size_t i) { total += i; }); });
  EXPECT_EQ(total.load(), 8u * 4950u);
}

TEST(Parallel, LoopsOnTwoThreadsAtOnceFinish) {
  std::atomic<size_t> total{0};
  std::vector<std::thread> callers;
  for (int t = 0; t < 4; ++t)
    callers.emplace_back([&] {
      for (int round = 0; round < 50; ++round)
        parallelFor(64, 3, [&](size_t i) { total += i; });
    });
  for (auto &c : callers)
    c.join();
  EXPECT_EQ(total.load(), 4u * 50u * 2016u);
}

TEST(Parallel, AnErrorReachesTheCallerAndTheNextLoopRuns) {
  EXPECT_THROW(parallelFor(100, 4,
                           [&](size_t i) {
                             if (i == 37)
                               throw std::runtime_error("index 37");
                           }),
               std::runtime_error);
  std::atomic<size_t> runs{0};
  parallelFor(100, 4, [&](size_t) { runs++; });
  EXPECT_EQ(runs.load(), 100u);
}

} // namespace
