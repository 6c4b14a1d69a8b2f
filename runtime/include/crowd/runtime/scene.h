// Scene files for crowdplay (JSON): the packs to load, instance count and placement, per-instance
// clip, outfit, time offset and speed, colour palettes per sub-mesh region, camera (with an
// optional keyframed path), light and triangle budget. Errors name the file, line and column.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/runtime/agents.h"
#include "crowd/runtime/track_palettes.h"

namespace crowd::runtime {

struct CameraKey {
  double time = 0;
  glm::dvec3 position{0}, target{0};
};

struct Camera {
  glm::dvec3 position{0, 1.6, 10}, target{0, 1, 0};
  double fovYDegrees = 50, nearPlane = 0.1, farPlane = 1000;
  std::vector<CameraKey> path; // empty: fixed camera
  bool loopPath = true;
  // Eye and target at time t along the path (linear between keys).
  void at(double t, glm::dvec3 &eye, glm::dvec3 &look) const;
};

// A crossfade an instance starts in: from scene clip `from` (-1: none), played at
// `seconds * speed + fromOffset`, over [start, start + seconds] of scene time.
struct ClipFade {
  int32_t from = -1;
  double fromOffset = 0, start = 0, seconds = 0;
};

// The scene's "switch": every instance changes clip after a seeded random interval of
// [minEvery, maxEvery] seconds (the first within maxEvery), to another of the scene's clips
// drawn by `weights`, crossfading over `fade` seconds (clip_switch.h).
struct ClipSwitching {
  double minEvery = 0, maxEvery = 0, fade = 0.3;
  std::vector<double> weights; // per scene clip
  uint64_t seed = 1;
  bool enabled() const { return maxEvery > 0; }
};

// One placed character. World transform: translation + rotation about +Y.
struct Instance {
  uint32_t pack = 0;
  glm::dvec3 position{0};
  double yaw = 0; // radians
  uint32_t clip = 0;
  double timeOffset = 0, speed = 1;
  uint32_t palette = 0;
  uint32_t outfit = 0; // indexes Scene::outfitNames
  ClipFade fade;
};

// The scene's "world" (Tecchia, Loscos & Chrysanthou): the instances are agents walking a baked environment
// (world.h). Paths resolve against the scene file's folder.
struct WorldSettings {
  std::string terrainPath;   // a crowdbake terrain pack; empty: no world
  std::string behaviourPath; // RGBA image of the terrain's grid: a behaviour per colour
  std::string callbackPath;  // RGBA image of the terrain's grid: a callback per colour
  struct BusStop {           // the "bus_stop" callback: holds agents, releasing them on a timer
    uint8_t colour[3] = {0, 0, 0};
    double every = 20; // seconds
  };
  std::vector<BusStop> busStops;
  std::vector<glm::vec2> attractors; // world x, z
  std::vector<SpawnArea> spawn;      // the instances, area by area
  uint32_t clips[3] = {0, 1, 2};     // scene clips played standing, walking, running
  double fade = 0.3;                 // seconds a clip change crossfades
  AgentSettings agents;
  bool enabled() const { return !terrainPath.empty(); }
};

struct Scene {
  std::string path;
  std::vector<std::string> packPaths; // resolved against the scene file's folder
  std::vector<std::string> packNames;
  // Per pack: its impostor pack ("" for none); instances of the impostor's clip draw as
  // impostors past the one-texel-per-pixel distance.
  std::vector<std::string> impostorPaths;
  // Clip names instances choose from (Instance::clip indexes it); resolved by the player.
  std::vector<std::string> clipNames;
  // Outfit names instances choose from (Instance::outfit indexes it), "" for the pack's first;
  // resolved by the player against each clothed pack's outfit table.
  std::vector<std::string> outfitNames = {""};
  std::vector<Instance> instances;
  ClipSwitching switching;
  // palettes[p] maps region (sub-mesh) names to colours; "default" applies to the rest.
  std::vector<std::vector<std::pair<std::string, glm::vec3>>> palettes;
  Camera camera;
  glm::vec3 lightDirection = glm::normalize(glm::vec3(0.4f, 1.0f, 0.6f));
  WorldSettings world;
  // Triangles the player may draw a frame (LOD chooses each instance's detail to fit); 0: none.
  uint64_t budget = 0;
  // Seconds of clip time whose instances share a palette (track_palettes.h: kClipSampleSlot,
  // each clip's sample step; 0, exact times).
  float paletteSlot = kClipSampleSlot;
};

// Parses and validates SCENE.json. `instanceOverride` > 0 replaces the scene's count (the
// placement rule stays). Throws crowd::Error "FILE:LINE:COLUMN: what" on a bad file.
Scene loadScene(const std::string &path, size_t instanceOverride = 0);
Scene parseScene(const std::string &text, const std::string &path, size_t instanceOverride = 0);

} // namespace crowd::runtime
