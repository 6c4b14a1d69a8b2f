// The cloth bake's options checked, stage by stage (a manifest's reader needs these alone).
#include "crowd/bake/cloth_bake.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "crowd/formats/error.h"

namespace crowd {

void ClothCacheOptions::validate() const {
  if (!std::isfinite(fps) || fps < 0.0 || fps > 1000.0)
    throw Error("fps: " + std::to_string(fps) + " is outside 0..1000 (0: the file's)");
  if (!(orderTolerance > 0.0) || orderTolerance > 1.0)
    throw Error("order tolerance: must be in (0, 1]");
}

void LoopSearchOptions::validate() const {
  if (!std::isfinite(cycleFrames) || cycleFrames < 2.0)
    throw Error("cycle: " + std::to_string(cycleFrames) +
                " cache frames per body-clip cycle; a cycle needs at least 2 frames");
  if (candidates < 1 || candidates > 100)
    throw Error("candidates: " + std::to_string(candidates) + " is outside 1..100");
  if (!std::isfinite(velocityWeight) || velocityWeight < 0.0)
    throw Error("velocity-weight: must be a finite number >= 0");
  if (window > 16)
    throw Error("window: " + std::to_string(window) + " frames is over 16");
  if (minCycles < 1)
    throw Error("min-cycles: must be at least 1");
  if (maxCycles != 0 && maxCycles < minCycles)
    throw Error("max-cycles: " + std::to_string(maxCycles) + " is under min-cycles " +
                std::to_string(minCycles));
}

void EdgeMatchOptions::validate() const {
  if (views < 1 || views > 64)
    throw Error("views: " + std::to_string(views) + " is outside 1..64");
  if (pixels < 16 || pixels > 2048)
    throw Error("pixels: " + std::to_string(pixels) + " is outside 16..2048");
  if (!(cannyLow > 0.0) || !(cannyHigh >= cannyLow) || !std::isfinite(cannyHigh))
    throw Error("canny thresholds: need 0 < low <= high, got " + std::to_string(cannyLow) +
                " and " + std::to_string(cannyHigh));
}

void ClothLoopOptions::validate() const {
  search.validate();
  edges.validate();
  if (!(maxJumpRatio > 0.0) || maxJumpRatio > 10.0)
    throw Error("max-jump: " + std::to_string(maxJumpRatio) + " is outside (0, 10]");
  if (!(maxToMedian > 0.0) || maxToMedian > 1.0)
    throw Error("max-to-median: " + std::to_string(maxToMedian) + " is outside (0, 1]");
  if (!(exactRatio > 0.0) || exactRatio > maxJumpRatio)
    throw Error("exact ratio: must be in (0, max-jump]");
}

void ClothBakeOptions::validate() const {
  cache.validate();
  ClothLoopOptions l = loop; // the cycle is the clip's, set by the bake: check the rest
  l.search.cycleFrames = std::max(l.search.cycleFrames, 2.0);
  l.validate();
  if (blend < -1 || blend > 100000)
    throw Error("blend: " + std::to_string(blend) + " is outside -1..100000 (-1: as needed)");
  if (!(pushMarginMm >= 0.0) || pushMarginMm > 100.0)
    throw Error("push margin: must be in 0..100 mm");
}

} // namespace crowd
