// A pack's joint transforms at a clip frame, from whichever animation it stores: the animation
// texture where it has one (texture_skinning.h), else its joint tracks decoded at the frame's
// time by the palette pass's CPU mirror (track_palettes.h). What the CPU-side consumers (pose,
// previews, pack diffs, cloth bounds) read, so that each works on both kinds of pack.
#pragma once
#include <cstdint>
#include <vector>

#include "crowd/formats/chunks.h"
#include "crowd/runtime/texture_skinning.h"

namespace crowd::runtime {

// Every joint of clip `clip` at `frame` + `alpha` (frameAt's split of a time).
std::vector<JointRows> sampleJoints(const pack::AnimationPack &p, size_t clip, uint32_t frame,
                                    float alpha);
// One joint of it. From tracks this decodes the whole palette: sample once per time where many
// joints are needed.
JointRows sampleJoint(const pack::AnimationPack &p, size_t clip, uint32_t frame, float alpha,
                      uint32_t joint);

} // namespace crowd::runtime
