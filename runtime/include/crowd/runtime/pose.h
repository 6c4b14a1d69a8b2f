// The mesh exactly as the player draws it at one time: the sub-meshes an outfit draws
// (render_queues.h), cut at a LOD level (lod_select.h), skinned by the CPU mirror of the shader
// (texture_skinning.h) at the frame and blend the shader computes, garments with a cloth loop
// over the clip placed by the loop (cloth_playback.h). crowdbake pose writes it.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/formats/chunks.h"
#include "crowd/runtime/cloth_playback.h"

namespace crowd::runtime {

struct PoseOptions {
  std::string clip;         // "": the first clip; a pack without clips draws the bind pose
  std::string outfit;       // "": the first outfit of a clothed pack
  uint32_t lodVertices = 0; // a LOD cut at this many vertices; 0: full detail
};

// What is drawn, whatever the time: the pack's vertices the chosen triangles use (increasing)
// and the triangles, indexing into that list. Unknown clip or outfit names and a LOD cut out of
// range throw crowd::Error, listing what there is.
struct PoseMesh {
  const pack::Clip *clip = nullptr; // null: the bind pose
  std::string outfit;               // "" for a pack without outfits
  std::vector<uint32_t> vertices;
  std::vector<uint32_t> indices;
  // The sub-meshes drawn, in order, and where each one's triangles start in `indices` (one
  // more start: the end).
  std::vector<uint32_t> subMeshes, subMeshStarts;
  ClothBuffers cloth; // the pack's cloth loops
};
PoseMesh poseMesh(const pack::AnimationPack &pack, const PoseOptions &options,
                  ClothLoops cloths = {});

// Positions and (unnormalized, as the shader passes them on) normals of mesh.vertices at
// `seconds` into the clip: looping clips wrap, others clamp, as the player does. A looped
// garment's normals, and a flat-shaded vertex's (stored as zero), are their posed faces'
// (area-weighted: the player shades each face with its own).
void poseAt(const pack::AnimationPack &pack, const PoseMesh &mesh, float seconds,
            std::vector<glm::vec3> &positions, std::vector<glm::vec3> &normals);

// For each vertex marked in `faceted`: its normal becomes the sum of the (area-weighted) normals
// of the triangles using it; the others keep theirs. How a cloth loop's or flat-shaded vertex is
// lit by the CPU mirror and the impostor bake.
void faceNormals(const std::vector<glm::vec3> &positions, const std::vector<uint32_t> &indices,
                 const std::vector<uint8_t> &faceted, std::vector<glm::vec3> &normals);

} // namespace crowd::runtime
