// Where a clip's baked frames sit and the joint textures made from them: the frame plan for a
// rate, the source's own key rate, the seeded times every error is measured at, the stored
// precisions, and the animation and skin-weight textures.
#pragma once
#include <string>
#include <vector>

#include "crowd/bake/character.h"
#include "crowd/formats/chunks.h"

namespace crowd {

// A stored precision: how joints are encoded and in which texel format.
struct Precision {
  std::string name; // "float", "half", "qts", "qts-half"
  pack::JointEncoding encoding;
  pack::TexelFormat format;
  double bytesPerJointPerFrame() const {
    return pack::texelsPerJoint(encoding) * pack::bytesPerTexel(format);
  }
  // One frame of `jointCount` joints, of which `matrixJoints` fall back to matrix rows (one
  // texel more each) where the encoding is a quaternion one.
  uint64_t frameBytes(size_t jointCount, size_t matrixJoints) const {
    const size_t extra = encoding == pack::JointEncoding::Matrix3x4 ? 0 : matrixJoints;
    return uint64_t(jointCount * pack::texelsPerJoint(encoding) + extra) *
           pack::bytesPerTexel(format);
  }
};
const std::vector<Precision> &precisions();
const Precision &precisionByName(const std::string &name); // throws on an unknown name

// A clip's frames at a rate: frame i sits at start + i * step, the last on the clip's end.
struct ClipFrames {
  const AnimationClip *clip; // null: the rest pose
  std::string name;
  double start, step;
  uint32_t count;
  double fps; // the rate adjusted so the last frame lands on the end time
};
// Throws when the clip would need kClipFrames frames or more.
ClipFrames planFrames(const AnimationClip &clip, double fps);

// Frames per second that put a frame on every key of the clip's densest channel (30 when the
// clip has one key), capped at 1000.
double sourceRate(const AnimationClip &clip);

// Seeded random times per clip at which the player's pose is measured, besides every frame time
// and every mid-frame time.
inline constexpr uint32_t kRandomTimesPerClip = 64;
// kRandomTimesPerClip times uniform over [0, duration), seconds into the clip, from a fixed seed
// per clip index: every bake of a clip measures at the same times.
std::vector<double> seededTimes(size_t clipIndex, double duration);

// The joints whose transforms a quaternion, translation and uniform scale cannot carry within
// `tolerance` (model units) at some of `frames` (each a joint matrix per joint): the ones that
// shear or scale non-uniformly. A joint's error is the largest over the bind-pose box of the
// vertices it moves. Ascending.
std::vector<uint32_t> matrixJointsFor(const SkinnedMesh &m, size_t jointCount,
                                      const std::vector<std::vector<glm::dmat4>> &frames,
                                      double tolerance);

// The animation texture of frames (each a joint matrix per joint): rows wrap, a frame never
// straddles two rows. A quaternion precision stores `matrixJoints` as matrix rows (encoding
// QtsWithMatrices). Throws when a frame is wider than maxWidth or the texture too tall.
pack::AnimationTexture buildAnimationTexture(const std::vector<std::vector<glm::dmat4>> &frames,
                                             size_t jointCount, const Precision &p,
                                             uint32_t maxWidth,
                                             const std::vector<uint32_t> &matrixJoints = {});
// The skin-weight texture: 2 texels per vertex (4 joint ids, 4 weights).
pack::SkinTexture buildSkinTexture(const SkinnedMesh &m, uint32_t maxWidth);

} // namespace crowd
