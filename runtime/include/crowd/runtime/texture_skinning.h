// CPU mirror of the player's skinning vertex shader: fetches a joint's transform for two
// frames from the animation texture, interpolates them exactly as the shader does, and skins a
// vertex with the ids and weights of the skin-weight texture. Single precision, like the GPU.
// The bake's accuracy check uses it, so the figures it reports are the figures the player gets.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/formats/chunks.h"

namespace crowd::runtime {

// Rows of a 3x4 affine transform: p' = (dot(r0, p1), dot(r1, p1), dot(r2, p1)), p1 = (p, 1).
using JointRows = std::array<glm::vec4, 3>;

// A matrix's top three rows, and the matrix back (its last row 0 0 0 1).
inline JointRows toRows(const glm::mat4 &m) {
  return {glm::vec4(m[0][0], m[1][0], m[2][0], m[3][0]),
          glm::vec4(m[0][1], m[1][1], m[2][1], m[3][1]),
          glm::vec4(m[0][2], m[1][2], m[2][2], m[3][2])};
}
inline glm::mat4 toMat4(const JointRows &rows) {
  return glm::transpose(glm::mat4(rows[0], rows[1], rows[2], glm::vec4(0, 0, 0, 1)));
}

// Transform of `joint` at `alpha` in [0, 1] between clip frames `frame` and `frame + 1`
// (the second is clamped to the clip's last frame): matrix rows blend linearly, quaternion
// frames screw-linearly (as dual quaternions), joint by joint as the texture stores them.
JointRows sampleJoint(const pack::AnimationTexture &texture, const pack::Clip &clip, uint32_t frame,
                      float alpha, uint32_t joint);

// Every joint at one clip time: sampleJoint for each, in joint order. Skinning many vertices at
// one time samples the joints once this way instead of once per influence (same numbers).
std::vector<JointRows> sampleJoints(const pack::AnimationTexture &texture, const pack::Clip &clip,
                                    uint32_t frame, float alpha);

// A joint's transform in a crossfade, `weight` of the way from `from` to `to` (0: `from`): both
// taken as a rotation, translation and uniform scale and blended as dual quaternions, the same
// screw-linear blend that qts frames use. What rows carry beyond that (shear, non-uniform scale)
// is lost during a fade, and only then.
JointRows blendJoints(const JointRows &from, const JointRows &to, float weight);

// Frame index and blend factor for a time in seconds since the clip started: looping clips
// wrap over frameCount - 1 intervals past either end (the closing frame equals the first within
// the loop test's tolerance; at the end itself it is the closing frame), others clamp.
void frameAt(const pack::Clip &clip, float seconds, uint32_t &frame, float &alpha);

// A time in a clip: its frame and blend factor (frameAt).
struct ClipTime {
  const pack::Clip *clip = nullptr;
  uint32_t frame = 0;
  float alpha = 0;
};
ClipTime clipTimeAt(const pack::Clip &clip, float seconds);

glm::vec3 skinVertex(const pack::AnimationTexture &texture, const pack::SkinTexture &skin,
                     const pack::Clip &clip, uint32_t frame, float alpha, uint32_t vertex,
                     const glm::vec3 &position);

// The same with the vertex's normal, skinned as the shader skins it (the weighted sum of the
// rotated normals; the fragment shader normalizes it).
struct SkinnedVertex {
  glm::vec3 position, normal;
};
SkinnedVertex skinVertex(const pack::AnimationTexture &texture, const pack::SkinTexture &skin,
                         const pack::Clip &clip, uint32_t frame, float alpha, uint32_t vertex,
                         const glm::vec3 &position, const glm::vec3 &normal);

// A vertex skinned with joint transforms sampled beforehand (`joints`: sampleJoints at the
// time): the same sum as skinVertex above. The skin's joint ids must be below joints.size().
SkinnedVertex skinVertex(const std::vector<JointRows> &joints, const pack::SkinTexture &skin,
                         uint32_t vertex, const glm::vec3 &position, const glm::vec3 &normal);
glm::vec3 skinVertex(const std::vector<JointRows> &joints, const pack::SkinTexture &skin,
                     uint32_t vertex, const glm::vec3 &position);

// A vertex in a crossfade from one clip time to another: each clip's joint as a rigid transform
// (matrix frames converted one by one, then blended screw-linearly), the two blended as
// blendJoints does. From weight 1 on, `to` alone as skinVertex gives it: matrix packs step from
// the screw-linear to the linear blend between frames when a fade ends.
// The bind-pose vertex morphed at a clip time: each of the two frames' active targets adds its
// offsets times its weight, the frames mixed by alpha (weights blend linearly, as glTF's linear
// weight keys do). Morphing comes before skinning; the shader's morphed() does the same.
SkinnedVertex morphVertex(const pack::Morphs &morphs, const ClipTime &at, uint32_t vertex,
                          SkinnedVertex bind);
// The same in a crossfade: the two clip times' offsets mixed by `weight` (1: `to` alone).
SkinnedVertex morphVertexFaded(const pack::Morphs &morphs, const ClipTime &from, const ClipTime &to,
                               float weight, uint32_t vertex, SkinnedVertex bind);

// The shader's form of an animation texture's layout (its JointTexels buffer): per joint 2 ints,
// its first texel within a frame and its texels (3: matrix rows, 2: quaternion, translation and
// scale). The frame's texels are AnimationTexture::frameTexels().
std::vector<int32_t> jointTexelWords(const pack::AnimationTexture &t);

// The shader's form of a pack's morph slots (its MorphSlots buffer): per slot 4 ints, the
// target's first offset pair in the offsets, first vertex, vertex count and the weight's bits.
// Without morphs, one frame of unused slots.
std::vector<int32_t> morphSlotWords(const pack::Morphs *morphs);

SkinnedVertex skinVertexFaded(const pack::AnimationTexture &texture, const pack::SkinTexture &skin,
                              const ClipTime &from, const ClipTime &to, float weight,
                              uint32_t vertex, const glm::vec3 &position, const glm::vec3 &normal);

} // namespace crowd::runtime
