// A scene's world (Tecchia, Loscos & Chrysanthou): the environment's terrain and the agents that move the scene's
// instances over it (agents.h), no GL. Each instance is an agent: it stands where its agent
// stands, faces where it walks, and plays the scene's idle, walk or run clip by its speed, the
// walk and run at the pace of its steps, crossfading when the clip changes (clip_switch.h's
// ClipState, which the renderer draws).
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "crowd/formats/terrain.h"
#include "crowd/runtime/agents.h"
#include "crowd/runtime/clip_switch.h"
#include "crowd/runtime/scene.h"

namespace crowd::runtime {

// An image decoded by the caller: RGBA8 rows, row 0 at the terrain's lowest z.
struct RgbaImage {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba;
};

// Where an instance stands and what it plays, for the renderer.
struct InstanceMotion {
  glm::vec3 position{0};
  float yaw = 0;
  ClipState clip;
  float speed = 1; // the clips' playback speed
};

class SceneWorld {
public:
  // The scene's world settings, its terrain pack's chunk and the images it names (empty when it
  // names none). Throws crowd::Error on images of another size than the terrain's grid, or
  // more instances than the walkable area holds.
  SceneWorld(const Scene &scene, pack::Terrain terrain, const RgbaImage &behaviours,
             const RgbaImage &callbacks);
  // Steps the agents up to `seconds` (fixed steps; a time before the last restarts them).
  void advanceTo(double seconds);
  // Per scene instance, at the last time advanced to.
  const std::vector<InstanceMotion> &motions() const { return motions_; }
  const pack::Terrain &terrain() const { return terrain_; }
  const Crowd &crowd() const { return *crowd_; }

private:
  void restart();
  Scene scene_;
  pack::Terrain terrain_;
  RgbaImage behaviours_, callbacks_;
  std::unique_ptr<Crowd> crowd_;
  std::vector<InstanceMotion> motions_;
  std::vector<float> still_; // per agent: seconds it has not moved
  bool started_ = false;     // advanced once since the last restart
  double last_ = 0;          // the time last advanced to
};

} // namespace crowd::runtime
