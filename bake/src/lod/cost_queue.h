// The queue bakeLod pops its cheapest collapse from: a candidate goes into a bucket by its
// cost's top 16 float bits (sign, exponent, 7 bits of mantissa), so pushing and popping take
// constant time, where a binary heap spent half the bake sifting mostly stale candidates.
// Candidates within 1/128 of each other's cost share a bucket and pop last pushed first: the
// order stays deterministic, and no collapse is taken before one costing under half as much. A
// bucket is a list threaded through one pool of nodes, popped nodes reused first (not a vector a
// bucket, which small meshes paid for in allocations).
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
    uint32_t slot = free_;
    if (slot != kNone)
      free_ = nodes_[slot].next, nodes_[slot].item = item;
    else
      slot = uint32_t(nodes_.size()), nodes_.push_back({item, kNone});
    nodes_[slot].next = head_[b];
    head_[b] = slot;
    occupied_[b >> 6] |= uint64_t(1) << (b & 63);
    lowest_ = b < lowest_ ? b : lowest_;
    ++size_;
  }
  bool empty() const { return size_ == 0; }
  void reserve(size_t items) { nodes_.reserve(items); }
  // The cheapest item (the queue must not be empty). Where the last bucket popped from is
  // empty, the next occupied one is found in occupied_, 64 buckets a step.
  T pop() {
    if (head_[lowest_] == kNone) {
      uint32_t word = lowest_ >> 6;
      uint64_t bits = occupied_[word] & (~uint64_t(0) << (lowest_ & 63));
      while (bits == 0)
        bits = occupied_[++word];
      lowest_ = word * 64 + uint32_t(std::countr_zero(bits));
    }
    const uint32_t slot = head_[lowest_];
    Node &node = nodes_[slot];
    head_[lowest_] = node.next;
    if (node.next != kNone) // the next pop's node: loading the popped one is the queue's stall
      __builtin_prefetch(&nodes_[node.next]);
    if (node.next == kNone)
      occupied_[lowest_ >> 6] &= ~(uint64_t(1) << (lowest_ & 63));
    node.next = free_;
    free_ = slot;
    --size_;
    return node.item;
  }
  // Whether an item of cost a pushed with one of cost b comes up first.
  static bool sooner(double a, double b) { return bucketOf(a) < bucketOf(b); }
  // Whether an item of this cost would come up after the last one popped's bucket.
  bool later(double cost) const { return bucketOf(cost) > lowest_; }
  void clear() {
    for (uint32_t word = 0; word < occupied_.size(); ++word)
      for (uint64_t bits = occupied_[word]; bits != 0; bits &= bits - 1)
        head_[word * 64 + uint32_t(std::countr_zero(bits))] = kNone;
    std::fill(occupied_.begin(), occupied_.end(), 0);
    nodes_.clear();
    free_ = kNone, lowest_ = kBuckets - 1, size_ = 0;
  }

private:
  static constexpr uint32_t kBuckets = (0x7F800000u >> 16) + 1; // +infinity is the last
  static constexpr uint32_t kNone = UINT32_MAX;
  static uint32_t bucketOf(double cost) {
    float f = float(cost);
    if (!(f > 0))
      return 0; // zero (and anything not a positive number) first
    uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    return bits >> 16;
  }
  struct Node {
    T item;
    uint32_t next; // the node pushed before it into its bucket, or the next free one
  };
  std::vector<Node> nodes_;
  std::vector<uint32_t> head_ = std::vector<uint32_t>(kBuckets, kNone); // a bucket's last pushed
  std::vector<uint64_t> occupied_ = std::vector<uint64_t>((kBuckets + 63) / 64); // a bit a bucket
  uint32_t free_ = kNone, lowest_ = kBuckets - 1;
  size_t size_ = 0;
};

} // namespace crowd::lod
