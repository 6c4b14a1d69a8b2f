// GPU side of crowdplay (OpenGL 4.5 core): uploads packs (mesh, animation and skin-weight
// textures, clip table) and a scene's instances, and draws them with skinned instancing — one
// instanced draw per sub-mesh per character type — or, for comparison, naively (one draw per
// instance per sub-mesh, instance data in uniforms). Needs a current GL 4.5 context.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/formats/chunks.h"
#include "crowd/runtime/scene.h"

namespace crowd::runtime {

struct DrawStats {
  uint32_t drawCalls = 0;
  uint32_t instances = 0;
  uint64_t triangles = 0;
};

class CrowdRenderer {
public:
  // Resolves every instance's clip and palette against its pack; throws crowd::Error naming the
  // scene, pack and clip when a clip is unknown.
  CrowdRenderer(const std::vector<pack::AnimationPack> &packs, const Scene &scene);
  ~CrowdRenderer();
  CrowdRenderer(const CrowdRenderer &) = delete;
  CrowdRenderer &operator=(const CrowdRenderer &) = delete;

  // Draws every instance at scene time `seconds` (all instances advance with one uniform).
  DrawStats draw(const glm::mat4 &viewProjection, float seconds, bool naive);

private:
  struct Character;
  std::vector<std::unique_ptr<Character>> characters_;
  unsigned program_ = 0;
  glm::vec3 light_;
};

// Compiles and links the embedded shaders; throws crowd::Error with the driver's log.
unsigned buildCrowdProgram();

} // namespace crowd::runtime
