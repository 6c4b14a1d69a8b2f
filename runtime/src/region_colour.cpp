#include "crowd/runtime/region_colour.h"

#include <glm/gtc/type_ptr.hpp>

namespace crowd::runtime {

std::array<float, 4> regionColour(const pack::AnimationPack &p, size_t s,
                                  const std::vector<std::pair<std::string, glm::vec3>> &palette) {
  const std::string &name = p.mesh.subMeshes[s].name;
  const std::string stem = name.substr(0, name.find_first_of("/@"));
  glm::vec3 col(0.8f);
  float textured = 1;
  if (p.outfits) {
    col = glm::make_vec3(&p.outfits->colours[s * 4]);
    textured = p.outfits->textured[s];
  } else {
    if (p.looks) {
      col = glm::make_vec3(&p.looks->colours[s * 4]);
      textured = p.looks->textured[s];
    }
    for (const auto &[region, value] : palette)
      if (region == "default")
        col = value;
  }
  for (const std::string &key : {stem, name})
    for (const auto &[region, value] : palette)
      if (region == key)
        col = value;
  return {col.r, col.g, col.b, textured};
}

} // namespace crowd::runtime
