// The morph-target chunk of an animation bake: the mesh's targets as offset ranges and, per baked
// frame, the kMorphSlots targets that move the mesh most at that frame's weights.
#pragma once
#include <optional>
#include <vector>

#include "crowd/bake/character.h"
#include "crowd/formats/chunks.h"
#include "crowd/runtime/texture_skinning.h"

namespace crowd {

// What did not fit a frame's kMorphSlots slots.
struct MorphOverflow {
  uint32_t mostActive = 0;   // the most targets active (weight not 0) in one frame
  uint32_t frames = 0;       // frames with more than kMorphSlots active: the least moving dropped
  double largestDropped = 0; // the largest offset a dropped target would have added, model units
};

// The chunk for the mesh and the weights of every frame (per frame, one per target, in the
// animation texture's frame order); nothing when the mesh has no targets.
std::optional<pack::Morphs> buildMorphs(const SkinnedMesh &mesh,
                                        const std::vector<std::vector<double>> &frameWeights,
                                        MorphOverflow *overflow = nullptr);

// Vertex v's bind-pose position as the player morphs it at a clip time (runtime::morphVertex),
// or as it is without morphs: what the accuracy checks skin.
glm::vec3 morphedBind(const SkinnedMesh &mesh, const std::optional<pack::Morphs> &morphs,
                      const runtime::ClipTime &at, uint32_t v);

} // namespace crowd
