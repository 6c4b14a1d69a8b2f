// What the player draws each frame, decided on the CPU: frustum culling by the pack's bounding
// sphere (the bake makes it hold the character at every frame of every clip), and a level of detail
// per visible instance so that the triangles drawn fit a global budget (the 2019 GPU-crowd seed,
// sec. 5.3, eq. (1)).
//
// Levels: a pack's LOD chunk allows any vertex count from its floor to the full mesh; the player
// keeps a ladder of them, each about `step` more triangles than the one below, and builds their
// index data once at load (measured against building exact counts every frame: see
// tests/bench/lod_select_bench.cpp). Selection is continuous and then rounds down a rung, so
// the budget still holds.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/formats/chunks.h"
#include "crowd/formats/impostor.h"

namespace crowd::runtime {

class Frustum {
public:
  // The six planes of a view-projection matrix, normalised, pointing inwards.
  explicit Frustum(const glm::mat4 &viewProjection);
  // False only when the sphere lies wholly outside one plane (conservative near the corners).
  bool sees(const glm::vec3 &centre, float radius) const {
    for (const auto &p : planes_)
      if (p.x * centre.x + p.y * centre.y + p.z * centre.z + p.w < -radius)
        return false;
    return true;
  }

private:
  std::array<glm::vec4, 6> planes_;
};

// The vertex counts a character can be drawn at, coarse to fine.
struct LodLevels {
  std::vector<uint32_t> vertices;  // increasing; the last is the full mesh
  std::vector<uint64_t> triangles; // over all sub-meshes, at each level
  // For t = 0..triangles.back(): the finest level with at most t triangles (0 when none is).
  std::vector<uint32_t> finestWithin;
};

// Without a LOD chunk: one level, the full mesh.
LodLevels lodLevels(const pack::AnimationPack &pack, double step = 0.02);

// The triangles of the mesh at `vertices` vertices: per sub-mesh (its start in the result in
// `starts`), the first triangleCount(s, v) triangles with each index followed through the
// collapse map until it is below v.
std::vector<uint32_t> lodIndices(const pack::AnimationPack &pack, uint32_t vertices,
                                 std::vector<uint32_t> &starts);

// Eq. (1)'s weight of an instance: w = A^(1/alpha) / D, alpha = 3, with A the projected area
// of its bounding sphere in pixels and D its distance (at least the radius). `pixelsPerUnit` is
// H / (2 tan(fovY / 2)): how many pixels a unit at distance 1 covers.
float lodWeight(float distanceSquared, float radius, float pixelsPerUnit);

struct Visible {
  float weight = 0;
  uint32_t character = 0; // its ladder in `ladders`
  uint32_t level = 0;     // chosen
};

// Chooses every visible instance's level. Each gets its floor, and the rest of `budget` is
// shared in proportion to the weights (eq. (1)); an instance takes the finest level within its
// share, and what the finest levels leave unused is shared again among the others. The total,
// returned, is <= budget unless the floors alone exceed it (then every instance is at its
// floor). budget 0: no budget, every instance at its finest level.
uint64_t chooseLevels(std::span<Visible> visible, std::span<const LodLevels> ladders,
                      uint64_t budget);

// What the renderer needs of the camera for one frame.
struct FrameView {
  glm::mat4 viewProjection{1};
  glm::vec3 eye{0};
  double fovY = 0.87; // radians
  int viewportHeight = 720;
};

enum class DrawPath { Instanced, Naive, Hybrid };

// An instance becomes an impostor this share past its switch distance and geometry again this
// share nearer, so none flickers at the boundary.
inline constexpr double kImpostorHysteresis = 0.1;

struct DrawOptions {
  DrawPath path = DrawPath::Hybrid;
  uint64_t budget = 0;    // triangles drawn (impostors count two); 0: no budget, full detail
  bool cull = true;       // false: draw off-screen instances too (the reference for culling)
  bool wholeBody = false; // clothed packs: the whole body under the garments (the naive method)
  // (0, 1]: every geometry instance at the finest level with at most this share of its full
  // detail's triangles, whatever the budget (a preview's fixed level); 0: chosen under the budget.
  double detail = 0;
  bool allImpostors =
      false; // hybrid: every instance with an impostor draws as one, at any distance
  // Packs with joint tracks (crowdbake anim --store both) skin from palettes the palette pass
  // decodes from them each frame, not from the animation texture. Packs of joint tracks alone
  // (--store tracks) always do.
  bool trackSkinning = false;
  bool timePalettes = false; // with it: the palette pass's GPU time in DrawStats (waits for it)
};

// The CPU half of a frame for a whole crowd, apart from GL so the benchmark times the very
// code the player runs: cull, split off impostors (hybrid), choose levels, and list each
// character's geometry instances sorted by level.
class CrowdSelection {
public:
  struct Character {
    float radius = 0;           // of the bounding sphere
    glm::vec3 boundLocal{0};    // its centre in the character's space
    glm::vec3 impostorLocal{0}; // the impostor sphere's
    const pack::Impostor *impostor = nullptr;
    std::vector<glm::vec3> bounds;  // per instance: world centre of the bounding sphere
    std::vector<glm::vec3> centres; // per instance: world centre of the impostor's sphere
    std::vector<uint8_t> eligible;  // per instance: plays the impostor's clip
    std::vector<uint8_t> far;       // per instance: an impostor now (hysteresis: kept)
    // Results of select(): geometry ids sorted by level, with runEnds[l] the end of level l's
    // run, and the impostor ids, nearest first.
    std::vector<uint32_t> ids, runEnds, impostorIds;
  };
  std::vector<Character> characters;
  std::vector<LodLevels> ladders; // per character

  // Adds a character type; its instances are added to characters.back(). `sphere` (centre,
  // radius), if given, replaces the mesh's bounding sphere (a larger one: cloth loops).
  void addCharacter(const pack::AnimationPack &pack, const pack::Impostor *impostor,
                    const std::array<float, 4> *sphere = nullptr);
  // World transform: rotation `yaw` about +Y, then `position`.
  void addInstance(const glm::vec3 &position, float yaw, bool eligible);
  // Moves instance i of character ci (an agent walking).
  void moveInstance(size_t ci, size_t i, const glm::vec3 &position, float yaw);

  struct Result {
    uint32_t visible = 0, impostors = 0;
    uint64_t triangles = 0; // the geometry's at the chosen levels, plus two per impostor
    double milliseconds = 0;
  };
  Result select(const FrameView &view, const DrawOptions &options);

private:
  std::vector<Visible> visible_;
  std::vector<uint32_t> instance_;
  std::vector<std::pair<float, uint32_t>> impostorOrder_; // squared distance, id
};

} // namespace crowd::runtime
