// A cloth cache as the cloth-loop bake reads it: checked against the garment it animates (a
// part, by material name, of an outfit glTF), at the cache's frame rate, in the body's root frame.
//   - The garment's vertices, in the order a cache lists them: every vertex its triangles use,
//     in the glTF's order (primitive by primitive). The cache must have as many (a clear error
//     otherwise), in the same order: frame 0 must lie on the garment skinned at the clip's start
//     (the median vertex within `orderTolerance` of the garment's rest diagonal; free cloth
//     swings, the median stays near). A cache whose vertices are shuffled fails this.
//   - Frame rate: the file's (MDD) or `fps` (PC2 stores none; then `fps` is required).
//   - Root frame: each frame's positions times the inverse of the skeleton's top joint's global
//     transform at that frame's clip time (cache frame f is clip time f / fps, wrapping), so a
//     clip that travels loops in place.
#pragma once
#include <string>
#include <vector>

#include "crowd/bake/character.h"
#include "crowd/bake/loop_search.h"
#include "crowd/support/point_cache.h"

namespace crowd {

struct ClothCacheOptions {
  double fps = 0.0;            // --fps: the cache's frame rate; 0: the file's
  double orderTolerance = 0.1; // of the garment's rest diagonal, for frame 0's median vertex
  void validate() const;
};

// The vertex ids of part `garment` of `outfit`, ascending (the cache's order).
std::vector<uint32_t> garmentVertices(const Character &outfit, const std::string &garment);

// The cache's frame rate: the file's, else options.fps; an error naming the file if neither.
double cacheFps(const PointCacheReader &cache, const ClothCacheOptions &options);

// Throws a clear error when the cache does not fit the garment (count, then order).
void checkGarment(PointCacheReader &cache, const Character &outfit,
                  const std::vector<uint32_t> &garment, const AnimationClip &clip,
                  const ClothCacheOptions &options);

// Whether the cache's frame rate fits the body. The loop search cannot tell a wrong rate: read
// at 30, four "cycles" of a 24 fps cache are five true ones and close as well, and the loop then
// plays 25% fast. The garment's body-bound vertices (the tenth nearest the skinned garment at
// frame 0: a waistband) follow the skinned garment at the true rate and drift from it at a wrong
// one: their mean distance from it, over up to 48 frames spread over the cache, at `fps` and at
// the common rates 24, 25, 30, 48, 50 and 60.
struct FrameRateFit {
  double residual = 0.0;     // at `fps`, model units
  double bestRate = 0.0;     // the common rate (other than `fps`) that fits best; 0: none tried
  double bestResidual = 0.0; // its mean distance
  // That rate fits clearly better: under half the residual, which is past 0.2% of the garment's
  // rest diagonal (cloth that follows no body, like noise, fits every rate alike).
  bool mismatch = false;
};
FrameRateFit fitFrameRate(PointCacheReader &cache, const Character &outfit,
                          const std::vector<uint32_t> &garment, const AnimationClip &clip,
                          double fps);

// The clip of that name, or an error listing the body's clips.
const AnimationClip &findClip(const Character &body, const std::string &name);

// The clip time of cache frame `frame` at `fps` (frame 0 at the clip's start, wrapping).
double cacheFrameTime(const AnimationClip &clip, uint32_t frame, double fps);

// Cache frame `frame` (at `fps`, wrapping over the clip) into `body`'s root frame: the inverse of
// the skeleton's top joint's global transform at that clip time (identity without joints).
glm::dmat4 toRootFrame(const Character &body, const AnimationClip &clip, uint32_t frame,
                       double fps);

// Frames of `cache` in `body`'s root frame at `fps`, for searchLoops. Holds references.
ClothFrames rootFrames(PointCacheReader &cache, const Character &body, const AnimationClip &clip,
                       double fps);

} // namespace crowd
