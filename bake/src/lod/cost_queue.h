// The queue bakeLod pops its cheapest collapse from. A binary heap of the ten candidates each
// triangle pushes (nine of ten stale by the time they come up) spent half the bake sifting; here
// a candidate goes into a bucket by its cost's top 16 float bits (sign, exponent, 7 bits of
// mantissa), so pushing and popping take constant time. Candidates within 1/128 of each other's
// cost share a bucket and pop last pushed first: the order stays deterministic, and no collapse
// is taken before one costing under half as much.
#pragma once
#include <algorithm>
#include <bit>
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
    occupied_[b >> 6] |= uint64_t(1) << (b & 63);
    lowest_ = b < lowest_ ? b : lowest_;
    ++size_;
  }
  bool empty() const { return size_ == 0; }
  // The cheapest item (the queue must not be empty). Where the last bucket popped from is
  // empty, the next occupied one is found in occupied_, 64 buckets a step.
  T pop() {
    if (buckets_[lowest_].empty()) {
      uint32_t word = lowest_ >> 6;
      uint64_t bits = occupied_[word] & (~uint64_t(0) << (lowest_ & 63));
      while (bits == 0)
        bits = occupied_[++word];
      lowest_ = word * 64 + uint32_t(std::countr_zero(bits));
    }
    std::vector<T> &bucket = buckets_[lowest_];
    T item = bucket.back();
    bucket.pop_back();
    if (bucket.empty())
      occupied_[lowest_ >> 6] &= ~(uint64_t(1) << (lowest_ & 63));
    --size_;
    return item;
  }
  // Whether an item of this cost would come up after the last one popped's bucket.
  bool later(double cost) const { return bucketOf(cost) > lowest_; }
  void clear() {
    for (uint32_t word = 0; word < occupied_.size(); ++word)
      for (uint64_t bits = occupied_[word]; bits != 0; bits &= bits - 1)
        buckets_[word * 64 + uint32_t(std::countr_zero(bits))].clear();
    std::fill(occupied_.begin(), occupied_.end(), 0);
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
  std::vector<uint64_t> occupied_ = std::vector<uint64_t>((kBuckets + 63) / 64); // a bit a bucket
  uint32_t lowest_ = kBuckets - 1;
  size_t size_ = 0;
};

} // namespace crowd::lod
