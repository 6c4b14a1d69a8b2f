// Cloth loops in the player (crowdbake cloth): which mesh vertices play a loop, the loops'
// frames in the form the vertex shader reads them, and the shader's arithmetic on the CPU (its
// mirror, for the tests). A loop vertex is skinned rigidly to the skeleton's top joint: its
// position in the root frame, times the joint's bind matrix, is a bind-pose position that the
// joint's animation-texture transform carries to where the cache had it. The loop's frame
// follows the body clip's phase (clip cycles since the clip's start), so body and cloth play in
// step whatever the instance's time offset and speed, with no per-instance CPU work.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/formats/cloth.h"

namespace crowd::runtime {

using ClothLoops = std::span<const pack::ClothLoop>; // a pack's loops

// One loop as the shader's ClothLoops buffer holds it (std430: ivec4, vec4, vec4).
struct GpuClothLoop {
  int32_t first = 0;    // its first vertex-frame in the positions buffer
  int32_t vertices = 0; // loop vertices per frame
  int32_t frames = 0;   // 0: no loop for this (garment, clip)
  int32_t cycles = 0;   // clip cycles the loop spans
  float origin[3] = {}; // quantisation box
  float startCycle = 0; // the loop's first frame, in clip cycles since the clip's start
  float step[3] = {};
  float framesPerCycle = 0; // the cache's frames per clip cycle
};
static_assert(sizeof(GpuClothLoop) == 48);

struct ClothBuffers {
  uint32_t garments = 0; // looped garments: (outfit, garment) pairs
  uint32_t clips = 0;    // the pack's
  uint32_t rootJoint = 0;
  glm::mat4 rootBind{1.0f}; // the top joint's bind matrix (its inverse bind's inverse)
  // Per mesh vertex: its garment and loop vertex, or (-1, -1).
  std::vector<int32_t> vertices;
  std::vector<GpuClothLoop> loops; // per garment, per clip
  std::vector<uint32_t> positions; // per vertex-frame: x | y << 16, then z
  // The pack's bounding sphere grown to hold every loop frame (culling must not drop a swing).
  std::array<float, 4> sphere{};
  bool empty() const { return garments == 0; }
};

// Throws crowd::Error when a loop does not fit the pack (pack::clothVertexOf), or two loops of
// one garment place their vertices differently.
ClothBuffers clothBuffers(const pack::AnimationPack &pack, ClothLoops loops);

// The loop's two frames around clip time `clipSeconds` (scene time x speed + offset, not
// wrapped) and the blend between them, as the shader computes them.
struct LoopTime {
  uint32_t f0 = 0, f1 = 0;
  float alpha = 0;
};
LoopTime loopTimeAt(const pack::Clip &clip, const GpuClothLoop &loop, float clipSeconds);

// Loop vertex `vertex` at `t`, as a bind-pose position of the top joint (rootBind applied).
glm::vec3 clothBindPosition(const ClothBuffers &b, const GpuClothLoop &loop, const LoopTime &t,
                            uint32_t vertex);

// Where the shader draws mesh vertex `v` (before the instance's transform) at clip time
// `clipSeconds` of clip `clip`, when its garment has a loop over that clip; false otherwise
// (the vertex is skinned).
bool clothVertexAt(const pack::AnimationPack &pack, const ClothBuffers &b, uint32_t clip,
                   float clipSeconds, uint32_t v, glm::vec3 &position);

} // namespace crowd::runtime
