// Animation bake: samples every clip's joint matrices into one animation texture (rows wrap,
// a frame never straddles two rows), writes the skin-weight texture and the mesh, and
// measures the result against exact glTF evaluation with the player's own skinning math.
#pragma once
#include <algorithm>
#include <string>
#include <vector>

#include "crowd/bake/character.h"
#include "crowd/bake/report.h"
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
};
const std::vector<Precision> &precisions();
const Precision &precisionByName(const std::string &name); // throws on an unknown name

struct AnimBakeOptions {
  std::string clip;         // bake only this clip; empty: every clip
  double fps = 30;          // target sampling rate; each clip's rate is adjusted so its last
                            // frame lands exactly on its end time. 0: the source's own rate
                            // (its shortest key interval), so frames sit on the keys
  uint32_t maxWidth = 4096; // animation and skin texture width limit, texels
  std::string precision = "float";
  int threads = 0; // 0: all cores; output bytes never depend on it
  // Throws crowd::Error naming the first field out of range ("fps: ...").
  void validate() const;
};

// Seeded random times per clip at which the player's pose is measured, besides every frame time
// and every mid-frame time.
inline constexpr uint32_t kRandomTimesPerClip = 64;
// Millimetre figures are scaled to a character this tall (its rest pose's extent along +y).
inline constexpr double kReferenceHeightMm = 1800;

// Vertex errors of texture skinning against exact evaluation, in model units.
struct ClipAccuracy {
  std::string clip;
  uint32_t frames = 0;
  double maxAtFrames = 0, meanAtFrames = 0;
  double maxAtMidframes = 0, meanAtMidframes = 0;
  double maxAtRandom = 0, meanAtRandom = 0; // at kRandomTimesPerClip seeded times
  // What a user sees: the largest error at any time measured.
  double maxAnyTime() const { return std::max({maxAtFrames, maxAtMidframes, maxAtRandom}); }
};

struct PrecisionAccuracy {
  Precision precision;
  uint64_t textureBytes = 0;
  std::vector<ClipAccuracy> clips;
};

struct AnimBakeResult {
  pack::AnimationPack pack; // provenance is left to the caller
  double diagonal = 0;      // rest-pose bounding-box diagonal: the unit of relative errors
  double mmPerUnit = 0;     // model units to millimetres, the character kReferenceHeightMm tall
  bool heightIsDiagonal = false; // flat assets: the diagonal stands for the height
  std::vector<PrecisionAccuracy> accuracy; // every precision; the baked one is `baked`
  size_t baked = 0;
};

AnimBakeResult bakeAnimation(const Character &character, const AnimBakeOptions &options,
                             Reporter &reporter);

} // namespace crowd
