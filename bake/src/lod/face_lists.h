// Each vertex's faces, as bakeLod's collapses hand them on from the vertex that goes to the one
// it goes into: every list in one array, not a vector a vertex (an allocation each to make and
// free, and more as they grow). A list that outgrows its room moves to the end of the array with
// twice the room; when the moves have about doubled the array, every list packs into a new one.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace crowd::lod {

class FaceLists {
public:
  // room[v]: how many faces v's list holds before it moves.
  explicit FaceLists(const std::vector<uint32_t> &room) : list_(room.size()) {
    size_t at = 0;
    for (size_t v = 0; v < room.size(); ++v)
      list_[v] = {at, 0, room[v]}, at += room[v];
    items_.resize(at);
    packed_ = at;
  }
  // v's faces in the order they came (a span void after the next handOn).
  std::span<const uint32_t> operator[](uint32_t v) const {
    return {items_.data() + list_[v].begin, list_[v].size};
  }
  // Adds f to v's list, within the room the constructor gave it.
  void push(uint32_t v, uint32_t f) {
    List &l = list_[v];
    items_[l.begin + l.size++] = f;
  }
  // `from` has gone into `into`: into's list keeps its live faces in order, then takes from's,
  // and from's is emptied. live(f): whether face f is still there.
  template <class Live> void handOn(uint32_t from, uint32_t into, Live live) {
    const uint32_t needed = list_[into].size + list_[from].size;
    if (needed > list_[into].room)
      moveToEnd(into, 2 * needed);
    List &l = list_[into], &f = list_[from];
    uint32_t *dst = items_.data() + l.begin;
    uint32_t n = 0;
    for (uint32_t k = 0; k < l.size; ++k)
      if (live(dst[k]))
        dst[n++] = dst[k];
    for (uint32_t k = 0; k < f.size; ++k)
      if (const uint32_t face = items_[f.begin + k]; live(face))
        dst[n++] = face;
    l.size = n;
    f.size = 0;
  }

private:
  struct List {
    size_t begin;
    uint32_t size, room;
  };
  void moveToEnd(uint32_t v, uint32_t room) {
    if (items_.size() + room > 2 * packed_ + list_.size()) // packs cost O(lists): not too often
      pack();
    List &l = list_[v];
    const size_t begin = items_.size();
    items_.resize(begin + room);
    std::copy_n(items_.begin() + std::ptrdiff_t(l.begin), l.size,
                items_.begin() + std::ptrdiff_t(begin));
    l.begin = begin, l.room = room;
  }
  // Every list into a new array, in vertex order, with room for what it holds.
  void pack() {
    std::vector<uint32_t> packed;
    packed.reserve(items_.size() / 2);
    for (List &l : list_) {
      const size_t begin = packed.size();
      packed.insert(packed.end(), items_.begin() + std::ptrdiff_t(l.begin),
                    items_.begin() + std::ptrdiff_t(l.begin + l.size));
      l.begin = begin, l.room = l.size;
    }
    items_.swap(packed);
    packed_ = items_.size();
  }
  std::vector<List> list_;
  std::vector<uint32_t> items_;
  size_t packed_; // the array's size when last packed
};

} // namespace crowd::lod
