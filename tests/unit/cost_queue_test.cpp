// The LOD's bucket queue (bake/src/lod/cost_queue.h): cheapest bucket first, last pushed first
// within a bucket, whatever the interleaving of pushes and pops that reuses its nodes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "../../bake/src/lod/cost_queue.h"

namespace {

struct Item {
  double cost;
  int serial;
};

TEST(CostQueue, PopsCheapestBucketFirstAndLastPushedFirstWithin) {
  // Costs each in a bucket of its own (far more than 1/128 apart), 0 and +infinity at the ends.
  const double costs[] = {0.0, 1e-30, 0.5, 1.0, 2.0, 1e20, INFINITY};
  std::mt19937 random(17);
  crowd::lod::CostQueue<Item> queue;
  std::vector<Item> model; // what the queue holds, in push order
  int serial = 0;
  for (int round = 0; round < 3; ++round) {
    for (int step = 0; step < 20000; ++step) {
      if (model.empty() || random() % 3 != 0) {
        const Item item{costs[random() % std::size(costs)], serial++};
        queue.push(item.cost, item);
        model.push_back(item);
        continue;
      }
      // The model's answer: the lowest cost, and of those the last pushed.
      auto best = model.begin();
      for (auto it = model.begin(); it != model.end(); ++it)
        if (it->cost <= best->cost)
          best = it;
      ASSERT_FALSE(queue.empty());
      const Item got = queue.pop();
      ASSERT_EQ(got.serial, best->serial) << "round " << round << " step " << step;
      model.erase(best);
      for (double c : costs) // later(): past the bucket just popped from
        EXPECT_EQ(queue.later(c), c > got.cost);
    }
    queue.clear();
    model.clear();
    EXPECT_TRUE(queue.empty());
  }
}

TEST(CostQueue, NearCostsShareABucketAndDoNotReorder) {
  crowd::lod::CostQueue<Item> queue;
  // 1 and 1 + 2^-10 share a bucket (top 7 mantissa bits equal): last pushed first.
  queue.push(1.0, {1.0, 0});
  queue.push(1.0 + std::ldexp(1.0, -10), {1.0, 1});
  queue.push(1.0 + std::ldexp(1.0, -6), {1.0, 2}); // the next bucket up
  EXPECT_EQ(queue.pop().serial, 1);
  EXPECT_EQ(queue.pop().serial, 0);
  EXPECT_EQ(queue.pop().serial, 2);
  EXPECT_TRUE(queue.empty());
}

} // namespace
