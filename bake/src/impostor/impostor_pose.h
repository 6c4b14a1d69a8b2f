// The mesh as the impostor bake and its accuracy measure see it at one time of a clip: skinned
// and morphed positions and normals, flat-shaded vertices given their faces' normal.
#pragma once
#include <vector>

#include <glm/glm.hpp>

#include "crowd/bake/character.h"

namespace crowd::impostor {

struct Posed {
  std::vector<glm::vec3> positions, normals;
};

// The mesh posed by `clip` at `t` seconds.
Posed pose(const Character &c, const AnimationClip *clip, double t);

} // namespace crowd::impostor
