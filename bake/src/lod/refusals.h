// bakeLod's memory of the collapses it refused, and why. Whether a may collapse into b depends on
// the faces around a and around b alone (their rings, seams, apexes and normals; the rest
// positions never move), and every collapse marks the vertices whose faces it changed: the one
// kept and its ring after. A refusal stands while neither end has been marked since, so the next
// pass over the edges need not try it again (at 16 poses, of RecursiveSkeletons' 1,008 tries in
// its last pass 931 stood, of Fox's 264, 163), and where the floor is not reached, the warning's
// reasons are read here instead of trying every edge once more both ways: 5-12% of the small
// models' bakes (tests/bench/lod_speed.sh), the same bytes. A bake that reaches its floor in one
// pass only pays for it: 1-3% of CesiumMan's, and 30 bytes a face (+30 MB on a 1M grid).
//
// A refusal is kept in a slot of the face that winds the edge: slot 2 * (3f + e) for the edge
// from f's corner e to corner e + 1, and 2 * (3f + e) + 1 for its reverse where the edge is open
// (no face winds it). A face's corners change only in a collapse that marks them all, so a slot
// whose edge has changed never holds a refusal that stands.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace crowd::lod {

// Why a collapse is not allowed (kNone: it is).
enum class Block : uint8_t { kNone, kNoEdge, kSeam, kManifold, kNormal };

class Refusals {
public:
  Refusals(size_t vertices, size_t faces)
      : changed_(vertices, 0), at_(6 * faces, 0), why_(6 * faces) {}
  // A collapse changed v's faces (call after collapsed()).
  void changed(uint32_t v) { changed_[v] = collapses_; }
  void collapsed() { ++collapses_; }
  void refuse(size_t slot, Block why) { at_[slot] = collapses_, why_[slot] = why; }
  // Whether the refusal in `slot` of a collapse between a and b still stands.
  bool stands(size_t slot, uint32_t a, uint32_t b) const {
    return at_[slot] != 0 && at_[slot] >= std::max(changed_[a], changed_[b]);
  }
  Block why(size_t slot) const { return why_[slot]; }

private:
  uint32_t collapses_ = 1;        // 1 + the collapses so far; 0 in at_: never refused
  std::vector<uint32_t> changed_; // per vertex: collapses_ when its faces last changed
  std::vector<uint32_t> at_;      // per slot: collapses_ when the collapse was refused
  std::vector<Block> why_;
};

} // namespace crowd::lod
