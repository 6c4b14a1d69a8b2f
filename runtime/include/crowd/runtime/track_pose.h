// Poses from compressed joint tracks (formats/joint_tracks.h), in single precision as a shader
// decodes them: a clip time's two samples, each track interpolated as glTF interpolates it
// (slerp, lerp, or held), composed local to global along the hierarchy, times the inverse binds.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "crowd/formats/joint_tracks.h"

namespace crowd::runtime {

// Where a time falls in a clip's samples: `alpha` of the way from `first` to `second`. Times
// before the start or past the end clamp; at a cut the later sample holds.
struct SampleSpan {
  uint32_t first = 0, second = 0;
  float alpha = 0;
};
SampleSpan sampleSpan(const pack::TrackClip &clip, float seconds);

// Spherical interpolation along the shorter arc; a normalized lerp where the two are within
// about 2 degrees, where float slerp loses more than it keeps.
glm::quat slerpShorter(glm::quat a, glm::quat b, float s);

// A stored rotation (three of x, y, z, w in that order, `dropped` (0 w, 1 x, 2 y, 3 z) rebuilt
// >= 0) as the palette pass decodes it: unit length, also where quantization put the three past
// the unit sphere.
glm::quat trackRotation(const std::array<float, 3> &stored, uint32_t dropped = 0);

// Every node's local transform at a time.
struct LocalPose {
  std::vector<glm::quat> rotation;
  std::vector<glm::vec3> translation, scale;
};
LocalPose decodeLocalPose(const pack::TrackSkeleton &skeleton, const pack::TrackClip &clip,
                          float seconds);

// Joint matrices (global transform x inverse bind, 16 floats per joint column-major, as
// pack::Skeleton stores them) of a local pose.
std::vector<glm::mat4> skinningPalette(const pack::TrackSkeleton &skeleton, const LocalPose &pose,
                                       const std::vector<float> &inverseBind);

} // namespace crowd::runtime
