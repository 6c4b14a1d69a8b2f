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

} // namespace crowd::samples
