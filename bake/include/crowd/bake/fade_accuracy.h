// The error of crossfades between a pack's clips, as the player draws them: at seeded times and
// weights, the fade of the baked frames (runtime::skinVertexFaded) against the exact fade: the
// glTF's own joints at both clips' times, blended by the player's rule (runtime::blendJoints);
// for a pack of joint tracks alone, the fade of its decoded local poses
// (runtime::decodePalette) against the glTF's local poses blended alike (blendLocals).
#pragma once
#include <vector>

#include <glm/glm.hpp>

#include "crowd/bake/anim_bake.h"

namespace crowd {

inline constexpr uint32_t kFadePairs = 12;         // ordered pairs of clips measured, at most
inline constexpr uint32_t kFadeSamplesPerPair = 8; // (time in each clip, weight) per pair

// Seconds into source clip `source` for `seconds` of play of its baked clip: wrapped as the
// player wraps a looping clip, clamped otherwise.
double sourceSeconds(const AnimationClip &source, const pack::Clip &baked, double seconds);

// The exact crossfade's joint matrices: `weight` of the way from `from` to `to`.
std::vector<glm::dmat4> blendedJoints(const std::vector<glm::dmat4> &from,
                                      const std::vector<glm::dmat4> &to, float weight);

// Fades between `sources[a]` and `sources[b]`, baked as pack clips a and b.
FadeAccuracy measureFades(const Character &c, const std::vector<const AnimationClip *> &sources,
                          const pack::AnimationPack &pack, int threads);

} // namespace crowd
