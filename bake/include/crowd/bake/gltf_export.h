// A character pack as a binary glTF another tool opens (Blender, three.js, an engine's
// importer): the character as the player draws it. The sub-meshes an outfit draws at a LOD cut,
// each a primitive with its material (base colour, the diffuse texture where it applies); the
// skeleton with its inverse binds; 4 influences a vertex (JOINTS_0, WEIGHTS_0); every clip an
// animation of the poses the player decodes: from joint tracks, each track's own samples with
// its own interpolation (LINEAR, slerp for rotations, or STEP), which is how the player decodes
// them; from an animation texture, every stored frame as local translation, rotation and scale
// keys (LINEAR), where the player blends frames as dual quaternions; morph targets with a
// weights key per frame.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "crowd/bake/report.h"
#include "crowd/formats/chunks.h"

namespace crowd {

struct GltfExportOptions {
  std::string outfit;       // "": a clothed pack's first outfit
  uint32_t lodVertices = 0; // a LOD cut at this many vertices; 0: full detail
};

// Throws crowd::Error for an unknown outfit or a cut outside the pack's LOD. What a glTF node
// cannot hold (a joint transform that shears) is warned through `reporter`; cloth loops, which
// are not an AnimationPack's, are the caller's to report.
std::vector<uint8_t> exportGltf(const pack::AnimationPack &pack, const GltfExportOptions &options,
                                Reporter &reporter);

} // namespace crowd
