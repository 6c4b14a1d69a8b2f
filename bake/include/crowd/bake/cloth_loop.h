// The cloth-loop choice: pass 1 (loop_search.h) keeps the candidates, pass 2 (edge_match.h)
// measures each seam's edge distance, and the smallest sum over the views wins. Then the
// verdict. A hard cut is acceptable when the seam jumps at most `maxJumpRatio` (1 by default)
// of the mean per-frame vertex motion, and its velocity at most as much of the mean
// per-frame velocity change, and either
//   - the seam is clearly better than a typical one: its pass-1 distance at most
//     `maxToMedian` of the median seam's. A cache of independent random frames passes the
//     ratios (its seams jump 1.0 x and 0.82 x, sqrt(4/6), like any frame) but not this: every
//     seam is as bad as the median (0.96 x on noise.pc2; 0.15 to 0.32 x on the sample skirts);
//   - or the seam hardly jumps at all (both ratios at most `exactRatio`): cloth that has
//     settled into a period, where every seam is as good as the median.
// A rejected loop names the blend it would need: the frames over which a cross-fade spreads its
// jump down to `exactRatio`.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "crowd/bake/edge_match.h"
#include "crowd/bake/loop_search.h"

namespace crowd {

struct ClothLoopOptions {
  LoopSearchOptions search;
  EdgeMatchOptions edges;
  double maxJumpRatio = 1.0; // --max-jump: of the mean per-frame motion and velocity change
  double maxToMedian = 0.5;  // the best seam's distance against the median seam's
  double exactRatio = 0.1;   // jumps this small are a period, whatever the median
  void validate() const;
};

struct ClothLoopCandidate {
  LoopCandidate seam;                // pass 1's figures
  uint32_t pass1Rank = 0;            // 0: pass 1's best
  std::vector<double> edgeDistances; // pass 2, pixels per view
  double edgeDistance = 0.0;         // their sum
};

// The search's result (what pack::ClothLoop stores is cut from the cache around it).
struct LoopChoice {
  std::vector<ClothLoopCandidate> candidates; // in pass 2's order: the chosen one first
  double meanMotion = 0.0, meanVelocityChange = 0.0;
  // The chosen seam's jumps against them, and how far it beats the median seam of pass 1
  // (filtered distance; about 1 for a cache that never repeats).
  double positionRatio = 0.0, velocityRatio = 0.0, bestToMedian = 0.0;
  bool acceptable = false;
  uint32_t blendFrames = 0; // 0 when acceptable; else the cross-fade it would need
  std::string verdict;      // one line for the report and the log
  double pass1Seconds = 0.0, pass2Seconds = 0.0;
  // Pass 1's filtered distance of every (start, cycles), for charts: distances[(c - minCycles) x
  // frames + start], NaN where no loop of c cycles starts there (LoopSearch::distances).
  std::vector<double> distances;
  uint32_t minCycles = 0, maxCycles = 0, frames = 0;
};

// `indices`: the garment's triangles over the cache's vertices (pass 2 draws them).
LoopChoice chooseLoop(uint32_t frameCount, uint32_t vertexCount, const ClothFrames &frames,
                      const std::vector<uint32_t> &indices, const ClothLoopOptions &options);

} // namespace crowd
