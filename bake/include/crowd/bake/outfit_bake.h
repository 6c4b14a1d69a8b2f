// Outfit bake ("tagged" method of the WSCG 2009 clothed-crowds paper): a body template in
// sub-meshes and pre-fitted outfits skinned to its skeleton become one pack. For each outfit and
// body sub-mesh it decides, over every sampled frame of every clip, whether the sub-mesh is
// visible, hidden, or partial (drawn through an outfit-specific copy of its visible faces).
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "crowd/bake/anim_bake.h"
#include "crowd/bake/character.h"
#include "crowd/bake/lod_bake.h"
#include "crowd/bake/report.h"
#include "crowd/formats/cloth.h"

namespace crowd {

struct OutfitInput {
  std::string name; // the outfit's name in the pack
  Character character;
  // Cloth loops of its garments (crowdbake cloth): visibility and the hole check also test the
  // loops' frames, each garment where its loop has it.
  std::vector<pack::ClothLoop> loops;
};

struct VisibilityOptions {
  double fps = 30;        // clips are sampled at this rate, each frame landing on its end time
  uint32_t frameStep = 1; // test every k-th sampled frame (1: every frame), and each clip's last
  // Cloth loops: at most this many of each loop's frames, evenly spaced (0: every frame). On the
  // sample dress all 1,074 frames of its walk and run loops hide exactly the faces 32 a loop do,
  // at 8x the time.
  uint32_t loopFrames = 32;
  // Directions over a face's outward hemisphere: `rays` azimuths on the lowest ring (1 degree
  // up), rays / 3 rings up to the pole, denser near the horizon (24: 139 directions).
  uint32_t rays = 24;
  uint32_t points = 4; // points on a face rays leave from: 1 (centroid) or 4
  uint32_t ring = 1;   // faces this many vertex-neighbour steps from a visible face stay
  // A ground plane under the body's lowest point (over the tested frames) occludes too: no
  // camera looks from below the ground (off: the whole hemisphere, from below included).
  bool ground = true;
  int threads = 0; // 0: all cores; the result never depends on it
};

// The frames visibility and the hole check test: (clip, time) for every `step`-th frame of each
// clip sampled at `fps` (its last frame on the clip's end) and each clip's last; the rest pose
// when there is no clip.
std::vector<std::pair<const AnimationClip *, double>> outfitFrames(const Character &c, double fps,
                                                                   uint32_t step);

// A cloth loop on the merged mesh (body, then each outfit's garments): the mesh vertex of each
// loop vertex. `firstVertex[k]`: where outfit k's vertices start in `merged`.
struct PlacedLoop {
  size_t outfit = 0; // index into the outfits
  const AnimationClip *clip = nullptr;
  std::vector<uint32_t> vertices;
  pack::ClothLoop loop;
};
std::vector<PlacedLoop> placeLoops(const Character &merged, const std::vector<OutfitInput> &outfits,
                                   const std::vector<uint32_t> &firstVertex);

// A pose visibility and the hole check test: a clip time, or a loop's frame (the body at the
// clip time it plays with, the loop's garment where the loop has it).
struct OutfitPose {
  const AnimationClip *clip = nullptr;
  double time = 0;
  const PlacedLoop *loop = nullptr;
  uint32_t frame = 0;
};
// outfitFrames, then at most `loopFrames` frames of each loop, evenly spaced (0: every one).
std::vector<OutfitPose> outfitPoses(const Character &merged, double fps, uint32_t step,
                                    const std::vector<PlacedLoop> &loops, uint32_t loopFrames);
std::vector<glm::dvec3> posed(const Character &merged, const OutfitPose &pose);

// Which body faces the garments hide (true) in every tested frame from every direction of the
// face's outward hemisphere: rays from points on the face, nudged out along its normal, cast
// against the skinned garments and body at that frame (CGAL AABB tree). `garmentParts` are the
// parts of `merged` (body first) worn; see-through parts never occlude. Faces within `ring`
// steps of a visible face are kept visible. Returns one flag per body triangle. `loops` (those
// of the worn outfit) add their frames to the tested ones.
std::vector<uint8_t> hiddenBodyFaces(const Character &merged, uint32_t bodyTriangles,
                                     const std::vector<size_t> &garmentParts,
                                     const VisibilityOptions &options,
                                     const std::vector<PlacedLoop> &loops = {});

struct OutfitOptions {
  VisibilityOptions visibility;
  // Body sub-meshes: "material" (one per glTF material, as imported) or "joint" (each material's
  // faces split by the joint weighing most on them: finer regions, smaller outfit copies).
  std::string regions = "material";
  // A partial body sub-mesh gets an outfit-specific copy only when the copy leaves out at least
  // this share of its faces; below it the sub-mesh is drawn whole.
  double minSaving = 0.10;
  AnimBakeOptions anim; // the pack's animation texture
  // Continuous LOD of the merged mesh (body parts, outfit-specific copies, garments), applied
  // before the animation bake; none when empty.
  std::optional<LodOptions> lod;
  // After baking, test that no hole opens (checkHoles at every `check`-th frame; 0: no check): a
  // differing pixel fails the bake, naming the outfit and the body parts seen through.
  uint32_t check = 0;
  void validate() const; // throws crowd::Error naming the first field out of range
  // The character's animation options, the one way an outfit bake takes them: the pack's
  // animation, and the visibility's frame rate where the animation's is a number.
  void setAnimation(const AnimBakeOptions &a);
};

struct SubMeshCoverage {
  std::string subMesh;
  uint32_t faces = 0, hidden = 0; // hidden: after the safety ring
  std::string coverage;           // visible, hidden or partial
  bool keptWhole = false;         // some faces hidden, but below minSaving
};

struct OutfitFigures {
  std::string name;
  uint32_t garmentFaces = 0;
  uint32_t hiddenFaces = 0;  // body faces hidden (after the ring)
  uint32_t removedFaces = 0; // body faces not drawn with this outfit
  std::vector<SubMeshCoverage> subMeshes;
  double seconds = 0; // visibility time
};

// Proof that removing the hidden faces opens no hole: each outfit is rasterized naively (whole
// body + garments) and as the pack draws it, from the impostor camera set (azimuths x
// elevations, orthographic, around the bounding sphere) and player-like perspective views, at
// every k-th frame of every clip, with exact skinning. Pixels compare the source triangle each
// shows.
struct HoleCheckOptions {
  uint32_t frameStep = 4;
  uint32_t loopFrames = 32; // as VisibilityOptions::loopFrames
  uint32_t azimuths = 32, elevations = 8;
  uint32_t texels = 128; // image side
  int threads = 0;
};
struct HoleCheck {
  struct PerOutfit {
    std::string name;
    uint64_t images = 0, differingPixels = 0;
    uint32_t removed = 0;   // body faces the outfit does not draw
    uint32_t neverSeen = 0; // body faces no naive image shows
    uint32_t removedUnseen = 0;
    std::vector<uint32_t> leaked; // removed body faces some naive image shows (holes)
    // The image with the most differing pixels (none when differingPixels is 0): which pose
    // and camera, in words, and the removed body faces it shows.
    uint64_t worstPixels = 0;
    std::string worstFrame, worstView;
    std::vector<uint32_t> worstLeaked;
    double recall() const { return neverSeen ? double(removedUnseen) / neverSeen : 1.0; }
  };
  std::vector<PerOutfit> outfits;
  uint32_t frames = 0, views = 0;
};

struct OutfitBakeResult {
  AnimBakeResult anim; // the pack (with its outfit table) and its animation accuracy
  Character merged;    // body, outfit-specific copies and garments: the pack's mesh
  uint32_t bodyTriangles = 0;
  uint32_t bareHiddenFaces = 0; // body faces hidden with no outfit (by the body, the ground)
  // Per triangle of `merged`: the body triangle it copies, or itself (garments, body).
  std::vector<uint32_t> sourceTriangle;
  std::vector<float> lodColourChange; // with options.lod: LodResult::colourChange
  std::vector<OutfitFigures> outfits;
  uint32_t framesTested = 0;     // per outfit, over every clip (loop frames apart)
  std::vector<PlacedLoop> loops; // every outfit's cloth loops, on `merged`
  uint32_t loopFramesTested = 0; // over every loop
  // Faces stored (seed Table 2): naive = body + garments; pre-fitted = per outfit, its visible
  // body faces + garments; tagged = body + outfit-specific copies + garments.
  uint64_t naiveFaces = 0, prefittedFaces = 0, taggedFaces = 0, specificFaces = 0;
  HoleCheck holes; // with OutfitOptions::check (no outfits when it did not run)
};

// The body in its regions ("material" or "joint", as OutfitOptions::regions) with one outfit's
// garments appended after its parts: the outfit as seen from outside (hidden faces stay, being
// hidden), for impostors. Parts: the body's, then the garments in the outfit's order.
Character dressCharacter(const Character &body, const OutfitInput &outfit,
                         const std::string &regions, Reporter &reporter);

// Throws crowd::Error when an outfit has no skin, uses a joint the body lacks, or was bound in
// another bind pose, or when options.check finds a hole.
OutfitBakeResult bakeOutfits(const Character &body, const std::vector<OutfitInput> &outfits,
                             const OutfitOptions &options, Reporter &reporter);

HoleCheck checkHoles(const OutfitBakeResult &baked, const HoleCheckOptions &options);

} // namespace crowd
