// Skinning palettes from compressed joint tracks: what the player's palette pass
// (shaders/palette.comp) decodes on the GPU, laid out for it, and its CPU mirror. An instance's
// clip time (and, in a crossfade, the faded clip's time and the new clip's weight) is a palette
// request; instances whose requests are equal share one palette. A crossfade blends the two
// clips' local poses (slerp, lerp) before the hierarchy, as engines fade.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/formats/chunks.h"
#include "crowd/runtime/track_pose.h"

namespace crowd::runtime {

// A pack's tracks as the palette pass reads them: 32-bit words, floats as their bits.
struct TrackWords {
  static constexpr uint32_t kNodeWords = 16;  // parent, is matrix, 12 rest floats, 2 unused
  static constexpr uint32_t kJointWords = 20; // node, 3 unused, inverse bind (16, column-major)
  static constexpr uint32_t kClipWords = 4;   // first time, samples, first track, first word
  static constexpr uint32_t kTrackWords =
      8;                        // kind | step << 8 | bits << 16, first bit, min, extent
  std::vector<uint32_t> rig;    // every node, then every joint
  std::vector<uint32_t> tracks; // every clip's words, then every track of every clip
  std::vector<float> times;     // every clip's samples' times (a uniform table written out)
  std::vector<uint32_t> stream; // every clip's stream, one after another
  uint32_t nodes = 0, joints = 0, clips = 0;
};
// The most bits of samples one clip may hold for the pass (its bit offsets are 32-bit).
inline constexpr uint64_t kMaxClipStreamBits = uint64_t(UINT32_MAX);
// Throws crowd::Error when the pack has no tracks or a clip's samples pass kMaxClipStreamBits.
TrackWords trackWords(const pack::AnimationPack &p);

// Instances whose clip times fall in one slot share a palette: each time is taken to the nearest
// multiple of its clip's slot (clamped into the clip). kClipSampleSlot, the player's default:
// each clip's own sample step (the poses its samples hold, none between); 0: exact times. A
// crossfade's weight is never slotted.
inline constexpr float kClipSampleSlot = -1.0f;
inline constexpr float kMaxPaletteSlot = 10.0f; // seconds: longer, most clips would hold one pose
// Each clip's slot in seconds: `slot` where it is >= 0, else (kClipSampleSlot) the clip's sample
// step, the tick its tracks' times are whole multiples of (pack::timeTicks: a uniform table's
// step, a grid's where samples were dropped from one), else 1 / its fps.
std::vector<float> paletteSlots(const pack::AnimationPack &p, float slot = kClipSampleSlot);

// What one palette shows: `clip` at `seconds` into it; in a crossfade, blended with `from` at
// `fromSeconds`, `weight` of the way to `clip` (from = -1: no fade, weight 1).
struct PaletteRequest {
  float clip = 0, seconds = 0, from = -1, fromSeconds = 0, weight = 1;
  bool operator==(const PaletteRequest &) const = default;
};
// The request of an instance playing `params` (clip, time offset, speed, palette) with `fade`
// (clip faded from or -1, its time offset, fade start, fade length) at scene time `seconds`:
// a looping clip (the clip table's flag) wraps over its duration, others clamp; then each clip
// time goes to its clip's slot of `slots` (paletteSlots; none given: exact times).
PaletteRequest paletteRequest(const pack::AnimationPack &p, const glm::vec4 &params,
                              const glm::vec4 &fade, float seconds,
                              std::span<const float> slots = {});

// The CPU mirror of the pass: the joints' matrices (global transform x inverse bind).
std::vector<glm::mat4> decodePalette(const pack::AnimationPack &p, const PaletteRequest &r);
// Two local poses blended, `weight` of the way from `from` to `to`.
LocalPose blendPoses(const LocalPose &from, const LocalPose &to, float weight);

} // namespace crowd::runtime
