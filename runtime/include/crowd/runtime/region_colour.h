// The colour a sub-mesh is drawn in under one of a scene's palettes.
#pragma once
#include <array>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/formats/chunks.h"

namespace crowd::runtime {

// Sub-mesh `s` of `p` under `palette` (region name -> colour; "default": the rest): RGB, and in A
// how much the diffuse texture applies (0 or 1). The base is the material's (a clothed pack's
// outfit table, else the pack's looks; light grey and textured in a pack from before looks were
// stored); a palette entry for the sub-mesh's name, or for the name's first part ("skin" for
// "skin/spine" or "skin@dress"), replaces it, and so does "default" in an unclothed pack.
std::array<float, 4> regionColour(const pack::AnimationPack &p, size_t s,
                                  const std::vector<std::pair<std::string, glm::vec3>> &palette);

} // namespace crowd::runtime
