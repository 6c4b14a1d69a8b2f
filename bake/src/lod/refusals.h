// bakeLod's memory of the collapses it refused, and why. Whether a may collapse into b depends on
// the faces around a and around b alone (their rings, seams, apexes and normals; the rest
// positions never move), and every collapse marks the vertices whose faces it changed: the one
// kept and its ring after. A refusal stands while neither end has been marked since, so the next
// pass over the edges need not try it again, and where the floor is not reached, the warning's
// reasons are read here instead of trying every edge once more both ways. 12 bytes a face.
//
// A refusal is kept in the face corner whose edge it is: corner 3f + e for the edge from f's
// corner e to corner e + 1, one word holding when it was refused and why. The reverse of an open
// edge (no face winds it) goes in a map under the same corner. A face's corners change only in
// a collapse that marks them all, so a corner whose edge has changed never holds a refusal that
// stands.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "crowd/formats/error.h"

namespace crowd::lod {

// Why a collapse is not allowed (kNone: it is).
enum class Block : uint8_t { kNone, kNoEdge, kSeam, kManifold, kNormal };

class Refusals {
public:
  // Where a refusal is kept: the corner that winds its edge, or (reverse) the other way round.
  struct Slot {
    size_t corner;
    bool reverse;
  };
  Refusals(size_t vertices, size_t faces) : changed_(vertices, 0), at_(3 * faces, 0) {
    if (vertices >= kWhen) // each collapse removes a vertex: collapses_ stays below this
      throw Error("lod: more than " + std::to_string(kWhen - 1) + " vertices");
  }
  // A collapse changed v's faces (call after collapsed()).
  void changed(uint32_t v) { changed_[v] = collapses_; }
  void collapsed() { ++collapses_; }
  void refuse(Slot s, Block why) {
    (s.reverse ? reverse_[s.corner] : at_[s.corner]) = collapses_ | uint32_t(why) << kWhyShift;
  }
  // Whether the refusal in slot s of a collapse between a and b still stands.
  bool stands(Slot s, uint32_t a, uint32_t b) const {
    const uint32_t when = word(s) & (kWhen - 1);
    return when != 0 && when >= std::max(changed_[a], changed_[b]);
  }
  Block why(Slot s) const { return Block(word(s) >> kWhyShift); }

private:
  static constexpr uint32_t kWhyShift = 29, kWhen = uint32_t(1) << kWhyShift;
  uint32_t word(Slot s) const {
    if (!s.reverse)
      return at_[s.corner];
    const auto it = reverse_.find(s.corner);
    return it == reverse_.end() ? 0 : it->second;
  }
  uint32_t collapses_ = 1;        // 1 + the collapses so far; 0 in a word: never refused
  std::vector<uint32_t> changed_; // per vertex: collapses_ when its faces last changed
  std::vector<uint32_t> at_;      // per corner: collapses_ when refused | the Block's bits
  std::unordered_map<size_t, uint32_t> reverse_; // open edges' other way, by corner
};

} // namespace crowd::lod
