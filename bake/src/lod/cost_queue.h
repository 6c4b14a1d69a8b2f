// The queue bakeLod pops its cheapest collapse from. A binary heap of the ten candidates each
// triangle pushes (nine of ten stale by the time they come up) spent half the bake sifting; here
// a candidate goes into a bucket by its cost's top 16 float bits (sign, exponent, 7 bits of
// mantissa), so pushing and popping take constant time. Candidates within 1/128 of each other's
// cost share a bucket and pop last pushed first: the order stays deterministic, and no collapse
// is taken before one costing under half as much.
#pragma once
#include <cstdint>
#include <cstring>
#include <vector>

namespace crowd::lod {

template <class T> class CostQueue {
public:
  void push(double cost, const T &item) {
    const uint32_t b = bucketOf(cost);
    if (buckets_[b].capacity() == 0) // a bucket's first growth steps took 5% of the bake
      buckets_[b].reserve(16);
    buckets_[b].push_back(item);
    lowest_ = b < lowest_ ? b : lowest_;
    ++size_;
  }
  bool empty() const { return size_ == 0; }
  T pop() { // the queue must not be empty
    while (buckets_[lowest_].empty())
      ++lowest_;
    T item = buckets_[lowest_].back();
    buckets_[lowest_].pop_back();
    --size_;
    return item;
  }
  void clear() {
    for (auto &b : buckets_)
      b.clear();
    lowest_ = kBuckets - 1, size_ = 0;
  }

private:
  static constexpr uint32_t kBuckets = (0x7F800000u >> 16) + 1; // +infinity is the last
  static uint32_t bucketOf(double cost) {
    float f = float(cost);
    if (!(f > 0))
      return 0; // zero (and anything not a positive number) first
    uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    return bits >> 16;
  }
  std::vector<std::vector<T>> buckets_ = std::vector<std::vector<T>>(kBuckets);
  uint32_t lowest_ = kBuckets - 1;
  size_t size_ = 0;
};

} // namespace crowd::lod
