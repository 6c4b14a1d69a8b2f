// Compression of a character's clips into joint tracks (formats/joint_tracks.h) within an error
// budget measured on skinned vertices. Samples sit on the source keys (the union of the clip's
// channels' key times, cuts kept), so between keys the decoder interpolates as glTF does;
// CUBICSPLINE spans get samples added until linear interpolation follows them; then samples that
// interpolation between their neighbours reproduces (exact values, a share of the budget) are
// dropped, unless keeping every one takes fewer bytes or dropping misses the budget. Each track is
// default, constant or animated (a rotation drops the component farthest from 0 over the clip);
// an animated track's bit rate is the fewest bits that keep every joint's error (on the box of
// the vertices it moves) within the budget, raised on the track of the worst joint's chain that
// lowers its excess over the samples most per bit. Then every vertex is measured at
// the samples, between them and at seeded random times, with the runtime's single-precision
// decoder (runtime/track_pose.h); where that misses the budget, the joints' tolerance tightens.
#pragma once
#include <string>
#include <vector>

#include "crowd/bake/character.h"
#include "crowd/formats/joint_tracks.h"

namespace crowd {

// The skeleton the tracks drive, and per track node the Character node it stands for.
struct TrackRig {
  pack::TrackSkeleton skeleton;
  std::vector<int> sourceNode;
};
TrackRig trackRig(const Character &c);

struct TrackCompressionOptions {
  double errorBudgetMm = 1.0; // the largest vertex error at any time, mm at a 1.8 m character
  double mmPerUnit = 1.0;     // model units to those millimetres (millimetresPerUnit)
  int threads = 0;            // 0: all cores; output bytes never depend on it
  void validate() const;      // throws crowd::Error naming the field
};

// What a compressed clip holds and how far it errs, errors in millimetres at 1.8 m.
struct TrackClipFigures {
  std::string clip;
  uint32_t keys = 0;        // distinct source key times (a cut counts twice)
  uint32_t samples = 0;     // stored: the keys plus those added on CUBICSPLINE spans, less those
                            // interpolation between the others reproduces
  uint32_t sampledKeys = 0; // before any were dropped: where the errors at samples are measured
  uint32_t defaultTracks = 0, constantTracks = 0, animatedTracks = 0;
  double meanBits = 0; // per component, over the animated tracks
  uint64_t bytes = 0;  // pack::clipBytes
  double maxAtSamplesMm = 0, maxAtMidsMm = 0, maxAtRandomMm = 0;
  double meanAtRandomMm = 0;
  bool met = false; // every figure within the budget
  double maxAnyTimeMm() const;
};

struct CompressedClip {
  pack::TrackClip clip;
  TrackClipFigures figures;
};

// The morph weights the player blends between the pack's frames of a clip (morph_frames.h),
// which the errors then include; absent: the glTF's exact weights on both sides.
struct PlayedMorphs {
  const pack::Morphs *morphs = nullptr;
  const pack::Clip *clip = nullptr;
};

// Throws crowd::Error on a key that is NaN or infinite, naming the clip, node and key.
CompressedClip compressClip(const Character &c, const TrackRig &rig, const AnimationClip &clip,
                            size_t clipIndex, const TrackCompressionOptions &options,
                            const PlayedMorphs &played = {});

// The largest and mean vertex errors (model units) of `tracks` against exact evaluation of
// `clip`, at each of `seconds` (since the clip's start): the runtime decoder's palette skins
// every vertex in single precision, over the morph weights `played` gives. With a `cull` bound
// (of c's mesh) only the vertices whose bound exceeds the largest error found so far are skinned
// (the same largest, to the bit) and the mean is 0.
struct VertexErrors {
  double max = 0, mean = 0;
};
class SkinErrorBound;
VertexErrors trackErrors(const Character &c, const TrackRig &rig, const pack::TrackClip &tracks,
                         const AnimationClip &clip, const std::vector<double> &seconds, int threads,
                         const PlayedMorphs &played = {}, const SkinErrorBound *cull = nullptr);

} // namespace crowd
