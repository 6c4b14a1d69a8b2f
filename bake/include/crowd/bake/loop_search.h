// Pass 1 of the cloth-loop bake: where in a long cloth cache a loop of whole body-clip cycles
// closes best. For every start frame s and every loop length L = round(k x cycle), the two ends
// of the seam (frames s and s + L, which the loop plays as s + L - 1 then s) are compared by
// the distance of Kovar et al. 2002 over every cloth vertex: squared position differences plus
// `velocityWeight` x squared differences of the per-frame displacement. Like Video Textures
// (Schoedl et al. 2000), the distance is filtered along the diagonal (s + m, s + L + m), m in
// [-window, window], with binomial weights, so a loop also matches the motion around its seam.
// The best `candidates` (one per length within half a cycle of start) go on to pass 2.
//
// Frames are read a block of vertices at a time (all frames of 512 vertices, then the next),
// so the search holds frameCount x 512 positions, never the whole cache. Distances accumulate
// block by block in a fixed order, and each loop length is one thread's, so the result does
// not depend on the thread count.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

namespace crowd {

struct LoopSearchOptions {
  // Cache frames per body-clip cycle (clip duration x cache frame rate); required. Loop
  // lengths are whole cycles rounded to frames; the rounding is each candidate's phaseError.
  double cycleFrames = 0.0;
  uint32_t candidates = 5;     // --candidates: loops kept for pass 2
  double velocityWeight = 1.0; // against position; velocities are per-frame displacements
  uint32_t window = 2;         // half-width, in frames, of the filter along the diagonal
  uint32_t minCycles = 1;      // shortest loop, in cycles
  uint32_t maxCycles = 0;      // longest loop, in cycles (0: as long as the cache allows); a
                               // cap on the loop's bytes, which grow with its length
  int threads = 0;             // 0: all cores
  void validate() const;
};

struct LoopCandidate {
  uint32_t start = 0;      // first frame of the loop
  uint32_t length = 0;     // frames: plays start .. start + length - 1, then start again
  uint32_t cycles = 0;     // body-clip cycles in the loop
  double phaseError = 0.0; // |length - cycles x cycleFrames|, frames
  double distance = 0.0;   // filtered pass-1 distance, mean per vertex (cache units squared)
  // The seam unfiltered, mean over vertices (cache units): the position jump |p(s + L) - p(s)|
  // and the velocity jump |v(s + L) - v(s)|, v(f) = p(f + 1) - p(f) per frame.
  double positionJump = 0.0;
  double velocityJump = 0.0;
};

struct LoopSearch {
  std::vector<LoopCandidate> candidates; // best first
  // The yardsticks of a seam: mean over frames and vertices of the per-frame motion |v(f)| and
  // the per-frame velocity change |v(f + 1) - v(f)| (cache units).
  double meanMotion = 0.0;
  double meanVelocityChange = 0.0;
  // The filtered distance of every (start, cycles) for charts: distances[(c - minCycles) *
  // frameCount + start], NaN where no loop of c cycles can start there.
  std::vector<double> distances;
  uint32_t minCycles = 0, maxCycles = 0;
};

// Positions of vertices [first, first + count) at `frame`, in the body's root frame.
using ClothFrames = std::function<void(uint32_t frame, uint32_t first, uint32_t count,
                                       std::vector<glm::vec3> &out)>;

// Searches a cache of `frameCount` frames of `vertexCount` vertices. Throws crowd::Error when
// the cache holds fewer than two cycles (plus the filter window).
LoopSearch searchLoops(uint32_t frameCount, uint32_t vertexCount, const ClothFrames &frames,
                       const LoopSearchOptions &options);

} // namespace crowd
