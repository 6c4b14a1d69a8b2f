// The animation bake's accuracy: every precision's texture, played back as the player plays it
// (runtime/texture_skinning), against exact skinning at every frame time, every mid-frame time
// and kRandomTimesPerClip seeded random times of each clip.
#pragma once
#include <vector>

#include "crowd/bake/anim_bake.h"
#include "exact_frames.h"

namespace crowd {

// Each frame's bounding box of its exact positions, found on the way.
struct FrameBounds {
  std::vector<glm::dvec3> low, high;
};

// result.accuracy for every precision (the pack's clips, skin and morphs already made); the
// chosen precision's texture becomes result.pack.animation and its index result.baked.
FrameBounds measurePrecisions(const Character &c, const std::vector<ClipFrames> &clips,
                              const ExactFrames &frames, const std::vector<uint32_t> &matrixJoints,
                              const AnimBakeOptions &options, AnimBakeResult &result,
                              Reporter &reporter);

} // namespace crowd
