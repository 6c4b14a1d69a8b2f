// Run-time side of impostors, on the CPU: which stored views and frame show a character from a
// direction at a clip time, and what they show along a ray (impostor.vert and impostor.frag do the
// same on the GPU; the bake's accuracy check measures this), the distance past which an
// impostor texel is no bigger than a pixel, and the mip levels of a frame's atlases, built so
// that region ids are never averaged.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/formats/chunks.h"
#include "crowd/formats/impostor.h"

namespace crowd::runtime {

// A sampled view's camera frame: `dir` from the sphere centre towards the camera, `right` and
// `up` the image's axes.
struct ImpostorFrame {
  glm::dvec3 dir, right, up;
};

// One of the stored views an impostor blends.
struct ImpostorViewWeight {
  uint32_t azimuth = 0, elevation = 0; // the sampled direction
  size_t view = 0;                     // index into Impostor::views
  uint32_t layer = 0;                  // the frame whose atlas holds it
  bool flip = false;                   // mirrored: drawn flipped left-right
  double weight = 0;                   // the weights sum to 1
  ImpostorFrame frame;                 // of the sampled direction (impostorViewFrame)
};

// The frame shown and the stored views drawn for it, blended: the three sampled directions
// around the camera's on the (azimuth, elevation) grid, each cell split into two triangles, with
// barycentric weights (one view, weight 1, on a sampled direction; two above the top row).
struct ImpostorChoice {
  uint32_t frame = 0; // the nearest sampled frame
  int count = 0;      // views with a weight above 0, heaviest first
  ImpostorViewWeight views[3];
};

// `toEye`: from the character's sphere centre towards the camera, in the character's frame.
// `clipTime`: seconds since the clip's start (wrapped when `loop`).
ImpostorChoice chooseImpostorViews(const pack::Impostor &m, glm::dvec3 toEye, double clipTime,
                                   bool loop);

// What an impostor shows along one ray (impostor.frag's per-pixel work, on the CPU, at full
// detail): the ray meets each blended view's plane; there the view's coverage is read bilinearly
// from its four nearest texels, and the blend covers the pixel where the weighted coverage is at
// least half. The normal is the weighted mean of the views whose nearest texel is covered; the
// region and UV those of the heaviest such view (ids and UVs are never averaged).
struct ImpostorSample {
  bool covered = false;
  glm::dvec3 normal{0, 1, 0}; // object space, unit
  uint8_t region = 0;         // region id + 1
  glm::dvec2 uv{0, 0};        // wrapped into 0..1 (0 without UVs)
};
// `layers[f]`: frame f's decoded atlases, for every layer the choice names. `origin` and `ray`:
// a point on the ray and its direction (towards the character), in the character's frame.
ImpostorSample sampleImpostor(const pack::Impostor &m,
                              const std::vector<pack::ImpostorTexels> &layers,
                              const ImpostorChoice &choice, glm::dvec3 origin, glm::dvec3 ray);

ImpostorFrame impostorViewFrame(const pack::Impostor &m, uint32_t elevation, uint32_t azimuth);
ImpostorFrame impostorViewFrame(double azimuth, double elevation); // radians

// Distance from the camera at which one texel of the impostor covers one pixel, for a
// perspective camera with vertical field of view `fovY` (radians) drawing `viewportHeight`
// pixels. Farther than this, an impostor shows at least as much detail as the screen can.
double oneToOneDistance(const pack::Impostor &m, double fovY, int viewportHeight);

// The diffuse texture's texels per model unit on the mesh's surface (the square root of the
// texture area its triangles cover over their area; 0 without UVs or area). An impostor reads the
// diffuse texture at the mip level this gives for its distance, the same for its every pixel, so
// no pixel's level depends on its neighbours' (at a silhouette, uncovered ones).
double diffuseTexelsPerUnit(const pack::Mesh &mesh, uint32_t width, uint32_t height);

// Mip chain of one frame's atlases (level 0 first: the stored blocks). A texel of level k+1 covers
// a 2x2 block of level k (fewer at an odd edge): it is covered when at least half of them are; its
// region is the most frequent region among them (ties: the lower id) and its normal and UV those
// of the first texel of that region, so no id and no UV across a seam is ever averaged. Levels
// past 0 are encoded to BC5 again, as the pack's planes are.
struct ImpostorMip {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> normals; // BC5 blocks, octahedral
  std::vector<uint8_t> regions; // region id + 1 per texel
  std::vector<uint8_t> uvs;     // BC5 blocks, empty without UVs
};
std::vector<ImpostorMip> impostorMips(const pack::Impostor &m, uint32_t frame, uint32_t levels);

// How many mip levels the player builds: at most kImpostorMaxMipLevels, stopping where a level
// would mix whole views (half the smallest crop's shorter side).
inline constexpr uint32_t kImpostorMaxMipLevels = 6; // impostor.frag's per-level arrays too
uint32_t impostorMipLevels(const pack::Impostor &m);

} // namespace crowd::runtime
