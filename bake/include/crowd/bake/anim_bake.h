// Animation bake: samples every clip's joint matrices into one animation texture (rows wrap,
// a frame never straddles two rows), writes the skin-weight texture and the mesh, and
// measures the result against exact glTF evaluation with the player's own skinning math.
#pragma once
#include <algorithm>
#include <string>
#include <vector>

#include "crowd/bake/anim_budget.h"
#include "crowd/bake/anim_frames.h"
#include "crowd/bake/character.h"
#include "crowd/bake/morph_frames.h"
#include "crowd/bake/report.h"
#include "crowd/bake/track_compression.h"
#include "crowd/formats/chunks.h"

namespace crowd {

struct AnimBakeOptions {
  static constexpr double kFpsFromBudget = -1; // fps: the error budget picks each clip's rate
  static constexpr double kFpsSource = 0;      // fps: each clip's own key rate (sourceRate)
  std::string clip;                            // bake only this clip; empty: every clip
  // Sampling rate: a number forces it (each clip's rate is adjusted so its last frame lands
  // exactly on its end time), kFpsSource puts frames on the keys, kFpsFromBudget (default)
  // lets the budget choose from kRateLadder and the source rate.
  double fps = kFpsFromBudget;
  uint32_t maxWidth = 4096; // animation and skin texture width limit, texels
  // A name from precisions() forces it; "auto" (default) lets the budget choose.
  std::string precision = "auto";
  // The largest error the player may show at any time, millimetres at a kReferenceHeightMm
  // character: the budget picks the fewest bytes that meet it (see anim_budget.h).
  double errorBudgetMm = 1.0;
  int threads = 0; // 0: all cores; output bytes never depend on it
  // Which animation the pack stores, a name from stores(): "texture" (the ANIM chunk), "tracks"
  // (every clip compressed into joint tracks within the same budget, track_compression.h: the
  // TRAK chunk alone), "both", or "auto": of the texture and the tracks, the fewer bytes among
  // those meeting the budget on every clip.
  std::string store = "auto";
  static const std::vector<std::string> &stores();
  bool compressesTracks() const { return store != "texture"; }
  // The option that shapes the texture alone ("precision qts", "fps 30", "fps source"), or
  // empty: under store "auto" it selects the texture (storeAsked), and under "tracks" a
  // precision is an error (validate). A rate stays open to the tracks: it sets their pack's clip
  // table (the morph weights' frames).
  std::string shapesTheTexture() const;
  // The store the options ask for: `store`, but "texture" where it is "auto" and an option
  // shapes the texture; `reason` then says why.
  std::string storeAsked(std::string *reason = nullptr) const;
  // Throws crowd::Error naming the first field out of range ("fps: ...") or in conflict.
  void validate() const;
  // --fps and the manifest's "fps": "auto", "source" or a number in (0, 1000]; throws Error.
  static double parseFps(const std::string &text);
  static std::string fpsName(double fps); // the inverse, for reports and cache keys
};

// Millimetre figures are scaled to a character this tall (its rest pose's extent along +y).
inline constexpr double kReferenceHeightMm = 1800;
// Model units to those millimetres. A flat or lying asset (under a tenth of its rest diagonal
// tall) is scaled by its diagonal instead (`heightIsDiagonal` says so).
double millimetresPerUnit(const Character &c, bool *heightIsDiagonal = nullptr);

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

// Crossfades between the pack's clips against the exact fade (fade_accuracy.h), in model units.
struct FadeAccuracy {
  uint32_t pairs = 0; // ordered pairs of clips measured
  double maxError = 0, meanError = 0;
};

struct AnimBakeResult {
  pack::AnimationPack pack; // provenance is left to the caller
  double diagonal = 0;      // rest-pose bounding-box diagonal: the unit of relative errors
  double mmPerUnit = 0;     // model units to millimetres, the character kReferenceHeightMm tall
  bool heightIsDiagonal = false;           // flat assets: the diagonal stands for the height
  std::vector<PrecisionAccuracy> accuracy; // every precision; the baked one is `baked`
  size_t baked = 0;
  double errorBudgetMm = 0;
  BudgetChoice budget;         // how the rates and the precision were chosen, every option tried
  FadeAccuracy fades;          // at the baked precision
  MorphOverflow morphOverflow; // morph targets that did not fit a frame's slots
  std::vector<TrackClipFigures> tracks; // where tracks were compressed: per clip of the pack
  std::string stored;                   // "texture", "tracks" or "both": what the pack holds
  std::string storeReason;              // why, where AnimBakeOptions::store was "auto"
  bool storesTexture() const { return stored != "tracks"; }
  bool storesTracks() const { return stored != "texture"; }
  uint64_t textureBytes() const; // the baked precision's texels, stored or not
  uint64_t tracksBytes() const;  // the TRAK chunk's skeleton and clips; 0 without tracks
};

// The budget's choice of what a pack stores (--store auto), from each encoding's worst error at
// any time over every clip and its bytes: the fewer bytes among those meeting the budget, else
// the one erring less; the reason in words, with the figures.
struct StoreCandidate {
  double worstMm = 0;
  uint64_t bytes = 0;
};
struct StoreChoice {
  std::string stored, reason; // "texture" or "tracks"
};
StoreChoice chooseStore(double budgetMm, StoreCandidate texture, StoreCandidate tracks);

AnimBakeResult bakeAnimation(const Character &character, const AnimBakeOptions &options,
                             Reporter &reporter);

} // namespace crowd
