// Impostor bake: for sampled frames of a clip, orthographic views from azimuths x
// elevations over the upper hemisphere, drawn with the deterministic rasterizer as object-space
// normals, region ids and UVs, cropped to their silhouettes, shelf-packed into one atlas per frame
// and stored as the GPU samples them (pack::Impostor: BC5 normals and UVs, exact region bytes).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "crowd/bake/character.h"
#include "crowd/bake/report.h"
#include "crowd/formats/impostor.h"

namespace crowd {

struct ImpostorOptions {
  std::string clip;     // empty: the first clip (or the rest pose when there is none)
  uint32_t frames = 16; // frames sampled evenly over the clip
  uint32_t azimuths = 32, elevations = 8;
  uint32_t texels = 128; // a full view is texels x texels before cropping
  // Texels from the switch distance instead (when > 0): the fewest, rounded up to a multiple of
  // 4, for which one texel covers at most one pixel at this distance (model units) from the
  // impostor's sphere, on a viewport `screenHeight` pixels tall with a vertical field of view of
  // `fovDegrees`. The player switches to the impostor where a texel covers a pixel: at this
  // distance or up to 4 texels' worth nearer, so no texel is stored that no pixel shows.
  // At most limits::kAutoImpostorTexels (a nearer switch is clamped, with a warning).
  double switchDistance = 0;
  int screenHeight = 1080;
  double fovDegrees = 50;
  bool mirror = false; // store azimuths 0..A/2 only (needs even frames and azimuths)
  // Measure the baked atlas against the true render (measureImpostor) for the figures; it
  // changes no byte of the atlas.
  bool measure = false;
  int threads = 0;                       // 0: all cores; the bytes never depend on it
  uint64_t maxBytes = uint64_t(4) << 30; // memory guard on the uncropped views
  void validate() const;                 // throws crowd::Error naming the first field out of range
};

// What the block compression of the atlases costs, over every covered texel of every frame:
// the decoded normal's angle to the rendered one, and the decoded UV's distance (texture widths).
struct ImpostorCompression {
  uint64_t texels = 0;
  double normalMeanDeg = 0, normalMaxDeg = 0, uvMean = 0, uvMax = 0;
  uint32_t textureWidth = 0; // the diffuse texture's (0: none), for the UV error in its texels
  uint32_t regionBits = 8;   // region ids on the GPU (Impostor::regionBits)
};

struct ImpostorBakeResult {
  pack::Impostor impostor;
  double occupancy = 0;            // silhouette-crop texels / atlas texels
  uint64_t bytesPerFrame = 0;      // one frame's planes as the GPU holds them (bytesPerFrame)
  uint64_t naiveBytesPerFrame = 0; // 3 bytes a texel for every view uncropped
  ImpostorCompression compression;
  // Left-right mirroring measured (even frame counts of a clip; -1 otherwise): silhouette IoU of
  // each view against the view from the opposite azimuth half a clip later, flipped.
  double mirrorIouMin = -1, mirrorIouMean = -1;
};

ImpostorBakeResult bakeImpostor(const Character &character, const ImpostorOptions &options,
                                Reporter &reporter);

// The texels of a view for a sphere of `radius` under options.switchDistance (see there);
// bakeImpostor clamps them to limits::kAutoImpostorTexels, warning.
uint32_t texelsAtSwitchDistance(double radius, const ImpostorOptions &options);

// Accuracy of a baked impostor against the true render, for frame 0: each camera direction is
// drawn as the player draws it (runtime::sampleImpostor: the three stored views around it,
// blended, each on its best plane) and compared with the mesh rasterized from that direction at
// the same size.
struct ImpostorAccuracy {
  struct Figures {
    double iouMean = 0, iouMin = 1;             // silhouette intersection over union
    double normalMeanDeg = 0, normalMaxDeg = 0; // angle between stored and true normals
    double uvMean = 0, uvMax = 0; // distance between stored and true UVs (texture widths)
    // Mean IoU of each elevation row, lowest first: where between-view accuracy is lost.
    std::vector<double> iouMeanByElevation;
  };
  Figures atViews, betweenViews; // directions at the sampled views; halfway between them
  double worstAzimuthDeg = 0, worstElevationDeg = 0, worstIou = 1; // lowest IoU found
  // A slow orbit (kOrbitSteps a view) at the lowest row: the mean and largest per-pixel change of
  // a lit grey between consecutive steps, in 8-bit levels, geometry against impostor. Popping is
  // the impostor's largest change well above the geometry's.
  struct Popping {
    uint32_t steps = 0;
    double elevationDeg = 0;
    double geometryMean = 0, geometryMax = 0, impostorMean = 0, impostorMax = 0;
  } popping;
};
inline constexpr uint32_t kOrbitSteps = 8; // orbit steps between two stored azimuths
ImpostorAccuracy measureImpostor(const Character &character, const pack::Impostor &impostor,
                                 int threads = 0);

} // namespace crowd
