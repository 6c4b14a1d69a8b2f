// What the sample cloth simulation needs of the sample humanoid (samples.cpp): a garment as the
// outfit glTF writes it, and the skeleton posed by a clip at any time.
#pragma once
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace crowd::samples::rig {

// One primitive of a sample outfit, in the glTF's vertex order; the first `pinned` vertices
// follow the skin (the dress's bodice and the skirt's waistband), the rest hang free.
struct Garment {
  std::vector<glm::vec3> bind;
  std::vector<glm::u16vec4> joints;
  std::vector<glm::vec4> weights;
  std::vector<uint32_t> indices;
  uint32_t pinned = 0;
};
Garment dress();

// The skeleton at `seconds` into `clip` (wrapping): every joint's world matrix and skinning
// matrix (world x inverse bind).
struct Pose {
  std::vector<glm::mat4> world, skin;
};
Pose pose(const std::string &clip, double seconds);
double clipPeriod(const std::string &clip);
int joint(const std::string &name);

} // namespace crowd::samples::rig
