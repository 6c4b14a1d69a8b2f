// Every frame the animation bake stores, exactly: its joint matrices and morph weights in double.
// Its vertex positions are skinned again where needed, never kept for every frame at once (48
// bytes a vertex a frame: a character with many long clips would not fit).
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/bake/anim_frames.h"
#include "crowd/bake/character.h"

namespace crowd {

struct ExactFrames {
  std::vector<std::pair<size_t, uint32_t>> list; // per frame: its clip and index in the clip
  std::vector<std::vector<glm::dmat4>> joints;   // per frame
  std::vector<std::vector<double>> morphWeights; // per frame
  size_t count() const { return list.size(); }
};

ExactFrames sampleFrames(const Character &c, const std::vector<ClipFrames> &clips, int threads);

// Frame f's vertex positions, skinned in double.
std::vector<glm::dvec3> framePositions(const Character &c, const ExactFrames &frames, size_t f);

} // namespace crowd
