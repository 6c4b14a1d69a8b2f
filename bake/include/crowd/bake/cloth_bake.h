// The cloth-loop bake (crowdbake cloth, and a character manifest's "cloth" entries): a long
// cloth cache of one garment of an outfit, simulated over a body clip repeated, becomes a loop
// that plays in phase with the clip.
//   1. The cache is checked against the garment (cloth_input.h) and read in the body's root frame.
//   2. The loop is chosen (cloth_loop.h): pass 1 over every (start, whole cycles), pass 2 on
//      the candidates' edge images, then the verdict.
//   3. Blend only when needed: a seam the verdict rejects is cross-faded over the loop's last
//      `blend` frames towards the frames just before its start (which lead into the start), so
//      the last frame flows into the first. A blended vertex the cross-fade moved into the body
//      (skinned at that frame's clip time; the closest body face's outward side, through a CGAL
//      AABB tree) is pushed back out onto the surface plus `pushMargin`; how many and how far
//      are reported.
//   4. The loop's frames are quantised to 16 bits per axis over their box (pack::ClothLoop)
//      and the quantisation error is measured against the unquantised frames.
#pragma once
#include <string>

#include "crowd/bake/character.h"
#include "crowd/bake/cloth_input.h"
#include "crowd/bake/cloth_loop.h"
#include "crowd/bake/input_files.h"
#include "crowd/bake/report.h"
#include "crowd/formats/cloth.h"

namespace crowd {

struct ClothBakeOptions {
  ClothCacheOptions cache;
  ClothLoopOptions loop;
  // --blend K: cross-fade frames when the verdict rejects the seam; -1 (default): the frames
  // the verdict names; 0: always a hard cut. Never more than half the loop or the frames
  // before its start.
  int blend = -1;
  double pushMarginMm = 2.0; // how far outside the body a pushed vertex lands, at 1.8 m
  void validate() const;
};

struct ClothBakeResult {
  LoopChoice loop;             // the search, both passes and the verdict
  FrameRateFit rate;           // whether the cache's frame rate fits the body (cloth_input.h)
  pack::ClothLoop chunk;       // what the pack stores
  double mmPerUnit = 0.0;      // model units to millimetres, the body 1.8 m tall
  bool blendClamped = false;   // the blend asked for did not fit before the loop's start
  uint32_t pushedVertices = 0; // (frame, vertex) pairs pushed out of the body
  double pushMaxMm = 0.0, pushMeanMm = 0.0;
  double quantMaxMm = 0.0, quantMeanMm = 0.0; // stored against exact loop positions
  double seconds = 0.0;
};

// `cachePath` is read under `policy`. Throws crowd::Error with the file named on a cache that
// does not fit the garment, a clip or garment that does not exist, or a cache too short.
ClothBakeResult bakeClothLoop(const Character &body, const Character &outfit,
                              const std::string &outfitName, const std::string &garment,
                              const std::string &clip, const std::string &cachePath,
                              const InputPolicy &policy, const ClothBakeOptions &options,
                              Reporter &reporter);

} // namespace crowd
