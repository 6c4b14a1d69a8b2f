// GPU side of crowdplay (OpenGL 4.5 core): uploads packs (mesh, animation and skin-weight
// textures, clip table) and a scene's instances, and draws them with skinned instancing — one
// instanced draw per sub-mesh per character type — or, for comparison, naively (one draw per
// instance per sub-mesh, instance data in uniforms). Characters with an impostor pack draw
// hybrid: instances of the impostor's clip past the one-texel-per-pixel distance (with
// hysteresis) as impostors, all of one type in one instanced draw. Needs a current GL 4.5 context.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/formats/chunks.h"
#include "crowd/formats/impostor.h"
#include "crowd/runtime/scene.h"

namespace crowd::runtime {

struct DrawStats {
  uint32_t drawCalls = 0;
  uint32_t instances = 0;
  uint32_t impostors = 0; // of the instances, those drawn as impostors
  uint64_t triangles = 0; // two per impostor
};

// What the renderer needs of the camera for one frame.
struct FrameView {
  glm::mat4 viewProjection{1};
  glm::vec3 eye{0};
  double fovY = 0.87; // radians
  int viewportHeight = 720;
};

enum class DrawPath { Instanced, Naive, Hybrid };

class CrowdRenderer {
public:
  // Resolves every instance's clip and palette against its pack; throws crowd::Error naming the
  // scene, pack and clip when a clip is unknown.
  // `impostors[k]` (null for none) belongs to packs[k]; both must outlive the renderer.
  CrowdRenderer(const std::vector<pack::AnimationPack> &packs,
                const std::vector<const pack::Impostor *> &impostors, const Scene &scene);
  ~CrowdRenderer();
  CrowdRenderer(const CrowdRenderer &) = delete;
  CrowdRenderer &operator=(const CrowdRenderer &) = delete;

  // Draws every instance at scene time `seconds` (all instances advance with one uniform).
  // Hybrid falls back to instanced geometry for characters without an impostor.
  DrawStats draw(const FrameView &view, float seconds, DrawPath path);

private:
  struct Character;
  std::vector<std::unique_ptr<Character>> characters_;
  unsigned program_ = 0, impostorProgram_ = 0;
  glm::vec3 light_;
};

// Compiles and links embedded shaders; throws crowd::Error with the driver's log.
unsigned buildProgram(const char *vertex, const char *fragment, const char *name);

} // namespace crowd::runtime
