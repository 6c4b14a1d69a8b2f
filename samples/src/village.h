// The sample village's geometry (samples.cpp writes it as village.glb): an environment for the
// terrain bake, in metres, y up. Ground sloping up to the east with a flat square in the middle,
// a stepped terrace to the north, a planter too high to step onto, six buildings around the
// square and a bus stop (a bench, a back panel and a sign). Every face its own vertices (flat
// shading), one part per material.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace crowd::samples {

struct VillagePart {
  std::string material;
  glm::vec4 colour{1.0f};
  std::vector<glm::vec3> positions, normals;
  std::vector<uint32_t> indices;
};

std::vector<VillagePart> villageParts();

// The village's behaviour and callback images for the agents (runtime/agents.h), one RGBA pixel
// per cell of its terrain baked at the default 0.25 m (320 x 320), row 0 at z = -40: behaviours
// wander (green) everywhere but a band of the square that draws agents to the bus stop (blue,
// with the attractor kVillageBusStop), a market on the terrace where they stop a while (red)
// and the east edge where they turn back (yellow); the callbacks mark the bus stop's queue
// (kVillageBusStopColour).
inline constexpr uint32_t kVillageCells = 320;
inline constexpr float kVillageBusStop[2] = {-1.0f, 8.4f}; // x, z
inline constexpr uint8_t kVillageBusStopColour[3] = {0, 0, 255};
std::vector<uint8_t> villageBehaviours();
std::vector<uint8_t> villageCallbacks();

} // namespace crowd::samples
