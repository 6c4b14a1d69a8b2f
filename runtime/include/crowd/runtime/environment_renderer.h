// GPU side of a scene's world (OpenGL 4.5 core): the environment's mesh from a terrain pack,
// lit per pixel and shaded by its shadow height map (a point below its cell's shadow height is
// in a building's shadow, Tecchia, Loscos & Chrysanthou §4.5). Needs a current GL 4.5 context.
#pragma once
#include <glm/glm.hpp>

#include "crowd/formats/terrain.h"

namespace crowd::runtime {

class EnvironmentRenderer {
public:
  explicit EnvironmentRenderer(const pack::Terrain &terrain); // uploads; the terrain may go
  ~EnvironmentRenderer();
  EnvironmentRenderer(const EnvironmentRenderer &) = delete;
  EnvironmentRenderer &operator=(const EnvironmentRenderer &) = delete;
  void draw(const glm::mat4 &viewProjection, const glm::vec3 &lightDirection) const;
  // The shadow height map (R32F, a texel a cell) and its grid (origin x, z, 1 / cell, 1), for
  // the characters' shaders to darken what stands in a building's shadow.
  unsigned shadowHeights() const { return shadowTexture_; }
  glm::vec4 grid() const { return {grid_.x, grid_.y, grid_.z, 1.0f}; }

private:
  unsigned program_ = 0, vao_ = 0, buffers_[4] = {}, shadowTexture_ = 0;
  unsigned indexCount_ = 0;
  glm::vec4 grid_{0};
};

} // namespace crowd::runtime
