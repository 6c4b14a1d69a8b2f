// GPU side of crowdplay (OpenGL 4.5 core): uploads packs (mesh, LOD levels, animation and
// skin-weight textures, clip table) and a scene's instances, and draws them with skinned
// instancing — one multi-draw per sub-mesh per character type, a command per LOD level in use —
// or, for comparison, naively (one draw per instance per sub-mesh, instance data in uniforms,
// no culling, full detail). Instances outside the view frustum are skipped; under a triangle
// budget each visible one gets a level of detail (lod_select.h). Characters with an impostor
// pack draw hybrid: instances of the impostor's clip past the one-texel-per-pixel distance (with
// hysteresis) as impostors, all of one type in one instanced draw. Instances of a clothed pack
// (crowdbake outfits) draw their outfit's sub-meshes only, through per-sub-mesh render queues of
// the visible instances (render_queues.h). Instances changing clip (clip_switch.h) crossfade on
// the GPU. Packs with joint tracks can skin from palettes decoded on the GPU each frame
// (DrawOptions::trackSkinning, palette_pass.h). Garments with cloth loops (crowdbake cloth) play
// them in phase with the body clip (cloth_playback.h). A scene's world (world.h) moves the
// instances as agents over its environment, drawn first. Needs a current GL 4.5 context.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/formats/chunks.h"
#include "crowd/formats/impostor.h"
#include "crowd/runtime/clip_switch.h"
#include "crowd/runtime/cloth_playback.h"
#include "crowd/runtime/lod_select.h"
#include "crowd/runtime/scene.h"
#include "crowd/runtime/world.h"

namespace crowd::runtime {

class EnvironmentRenderer;
struct RenderQueues;

struct DrawStats {
  uint32_t drawCalls = 0;  // a multi-draw counts one
  uint32_t instances = 0;  // in the scene
  uint32_t visible = 0;    // of the instances, those inside the frustum (drawn)
  uint32_t impostors = 0;  // of the visible, those drawn as impostors
  uint64_t triangles = 0;  // two per impostor
  double cullSelectMs = 0; // CPU time of the clip schedule, culling, the impostor split, LOD
                           // selection and queues
  double agentsMs = 0;     // CPU time of a world's agents up to the frame and their placing
  uint32_t palettes = 0;   // DrawOptions::trackSkinning: palettes the palette pass decoded
  double paletteMs = 0;    // CPU time of their requests and the pass's calls
  double paletteGpuMs = 0; // DrawOptions::timePalettes: the pass's GPU time
};

class CrowdRenderer {
public:
  // Resolves every instance's clip, outfit and palette against its pack; throws crowd::Error
  // naming the scene, pack and clip or outfit when one is unknown.
  // `impostors[k]` (null for none) and `cloths[k]` (none if missing) belong to packs[k]; the
  // packs and impostors must outlive the renderer.
  CrowdRenderer(const std::vector<const pack::AnimationPack *> &packs,
                const std::vector<const pack::Impostor *> &impostors, const Scene &scene,
                const std::vector<ClothLoops> &cloths = {});
  ~CrowdRenderer();
  CrowdRenderer(const CrowdRenderer &) = delete;
  CrowdRenderer &operator=(const CrowdRenderer &) = delete;

  // Draws the crowd at scene time `seconds` (all instances advance with one uniform).
  // Hybrid falls back to instanced geometry for characters without an impostor.
  DrawStats draw(const FrameView &view, float seconds, const DrawOptions &options);

  // A scene with a "world": its agents place the instances and choose their clips from then
  // on, and its environment is drawn before them. The world must outlive the renderer.
  void attachWorld(SceneWorld &world);

  // Bytes of every impostor's textures and buffers on the GPU, every frame and mip level.
  uint64_t impostorBytes() const;

private:
  struct Character;
  // The constructor's stages for pack pi: its character checked against the scene (clips,
  // outfits, impostor, cloth) and its instances placed, then its GPU buffers and textures.
  void addCharacter(size_t pi, const pack::AnimationPack &p, const pack::Impostor *impostor,
                    const ClothLoops *cloth);
  void placeInstances(Character &c, size_t pi, const std::vector<uint32_t> &outfitOf);
  std::vector<uint32_t> lodIndexData(Character &c);
  void uploadGeometry(Character &c, const std::vector<uint32_t> &indices);
  static void uploadTextures(Character &c);
  // Writes character ci's instances where the world's agents stand, with their clips.
  void moveInstances(Character &c, size_t ci, double seconds);
  // With a world: the shadow pass's state and uniforms (on) or the normal pass's (off).
  void setShadowPass(bool on);
  // draw's passes: the frame's start (instances moved or their clips written, the environment
  // drawn), then per character its queues and palettes and, per pass, its geometry and
  // impostors.
  double beginFrame(const FrameView &view, double seconds, DrawStats &stats);
  RenderQueues &queueCharacter(Character &c, const CrowdSelection::Character &chosen,
                               bool wholeBody, DrawStats &stats);
  void runPalettes(Character &c, size_t ci, const CrowdSelection::Character &chosen, float seconds,
                   const DrawOptions &options, DrawStats &stats);
  void bindGeometry(const Character &c);
  void drawGeometry(const Character &c, const CrowdSelection::Character &chosen,
                    const RenderQueues &queues, bool naive, DrawStats &stats);
  void drawImpostors(const Character &c, const CrowdSelection::Character &chosen,
                     const FrameView &view, float seconds, bool shadow, DrawStats &stats);
  // One pass of character c: its geometry instances through their queues (or one by one on the
  // naive path) and its impostors; in the shadow pass, flat on the ground.
  void drawCharacter(const Character &c, const CrowdSelection::Character &chosen,
                     const RenderQueues &queues, const FrameView &view, float seconds, bool naive,
                     bool shadow, DrawStats &stats);
  SceneWorld *world_ = nullptr;
  std::unique_ptr<EnvironmentRenderer> environment_;
  // Writes the instances' clips and fades at `seconds` (the schedule's) into character ci's
  // instance data, and which of them may draw as impostors.
  void updateClips(Character &c, size_t ci, double seconds);
  // Instance i of character ci plays `s` at `speed`: its params and fade, and whether it may
  // draw as an impostor.
  void writeClip(Character &c, size_t ci, uint32_t i, const ClipState &s, float speed,
                 double seconds);
  Scene scene_;
  ClipSchedule schedule_;
  std::vector<std::unique_ptr<Character>> characters_;
  CrowdSelection selection_; // its characters are characters_, in order
  unsigned program_ = 0, impostorProgram_ = 0, paletteProgram_ = 0;
  glm::vec3 light_;
};

// Compiles and links embedded shaders; throws crowd::Error with the driver's log.
unsigned buildProgram(const char *vertex, const char *fragment, const char *name);
unsigned buildComputeProgram(const char *compute, const char *name);

} // namespace crowd::runtime
