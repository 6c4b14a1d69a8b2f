// Continuous LOD: the full edge-collapse sequence of a mesh, from all its
// triangles down to a floor, as arrays a renderer can cut at any vertex count. Collapses run on
// a welded mesh of flat arrays (lod/fan_mesh.h), cheapest quadric cost first (the largest over
// the bind pose and any poses given, lod/cost_queue.h); a UV seam vertex only collapses along its
// seam, a boundary vertex only along its boundary, a hard edge's (a normal seam's) also across it
// where the drawn colour changes by no more than the seam budget (lod/seam_shading.h), and no
// collapse leaves a triangle degenerate or turned more than `maxNormalDeviationDeg` from its
// full-detail normal, or the mesh non-manifold. No new vertices: every LOD vertex is an original
// one.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/bake/report.h"
#include "crowd/formats/chunks.h"

namespace crowd {

struct LodOptions {
  double floorFraction = 0.02; // stop at this share of the triangles (or no legal collapse)
  double maxNormalDeviationDeg = 75;
  uint32_t poses = 16; // applyLod: poses sampled evenly over all clips (0: the bind pose only)
  // The most a closed hard edge may change the drawn colour, 8-bit RGB distance under the
  // player's light at its worst direction (0: hard edges hold, as UV seams do).
  double seamBudget = 4;
  void validate() const; // throws crowd::Error naming the first field out of range
};

// What the seam budget weighs, per input vertex: its shading normal (zero: shaded by its face),
// the drawn colour's change per unit of normal change (255 x 0.75 x |albedo|, crowd.frag's light),
// and a key that two vertices at one position share where they differ in their normal alone (the
// same UV, or an untextured sub-mesh).
struct LodAppearance {
  std::vector<glm::vec3> normals;
  std::vector<float> colourScale;
  std::vector<uint32_t> key;
};

// Cut at v vertices: take the first triangleCount[v] triangles and follow each index through
// `collapse` until it is < v.
struct LodResult {
  std::vector<uint32_t> order;         // new vertex k is input vertex order[k]
  std::vector<uint32_t> collapse;      // new numbering: collapse[k] < k (collapse[0] = 0)
  std::vector<uint32_t> indices;       // the kept input triangles, reordered, new numbering
  std::vector<uint32_t> triangleCount; // for v = 0..vertices
  std::vector<float> error;            // quadric cost of the step that removed vertex k
  std::vector<uint32_t> source;        // per triangle: the input triangle
  std::vector<uint32_t> killedBy;      // per triangle: the vertex whose removal deletes it
                                       // (UINT32_MAX: none, it lasts to the floor)
  uint32_t floorVertices = 0;          // the fewest vertices the sequence reaches
  uint32_t inputTriangles = 0;         // before repairs (dropped faces are reported)
  size_t seamClosings = 0;             // render vertices drawn across a hard edge at the floor
  double seamColourChange = 0;         // the largest colour change that made, 8-bit RGB
  // The colour change (8-bit RGB) vertex k's removal made closing a hard edge (0: none): a cut
  // at v vertices shows the largest of k >= v.
  std::vector<float> colourChange;
};

struct Character;
struct SkinnedMesh;
// The triangles applyLod collapses, and how. A sub-mesh may repeat triangles of another on the
// same vertices (an outfit's copy of a partly covered body part): each distinct triangle is
// collapsed once (the LOD mesh would drop a repeat as a duplicate face and leave the copy
// empty) and its repeats follow it. Sub-meshes weld separately: where two touch (a sleeve on an
// arm) welding them would make edges with four faces; apart, each keeps its own border. A vertex's
// welding group is the sub-mesh of its last distinct triangle (a repeat does not move it) and its
// skin binding (joints and weights).
struct LodTriangles {
  std::vector<uint32_t> indices;               // the distinct triangles, in input order
  std::vector<std::vector<uint32_t>> inputsOf; // per distinct triangle, its input triangles
  std::vector<uint32_t> group;                 // per vertex: its sub-mesh and skin binding
};
LodTriangles lodTriangles(const SkinnedMesh &mesh);
// What the seam budget weighs for a mesh, per vertex (LodAppearance): its normal, its sub-mesh's
// colour scale, and its UV as the key where the sub-mesh is textured (one key where not).
LodAppearance lodAppearance(const SkinnedMesh &mesh);
// Per triangle, the sub-mesh holding it (0 for a triangle in none).
std::vector<uint32_t> triangleParts(const SkinnedMesh &mesh);
// `count` poses of the mesh, round robin over every clip at mid-interval times (none without
// clips): the poses applyLod's collapse costs take the worst of.
std::vector<std::vector<glm::vec3>> samplePoses(const Character &character, uint32_t count);

// Exact copies: a mesh written without indices, or one triangle at a time, repeats each shared
// corner as a vertex of its own, every attribute the same (position, normal, UV, skin, morphs).
// To the LOD each copy would be a seam and nothing would collapse. Copies within one sub-mesh
// weld into their first; a vertex two sub-meshes use, or one in `keep`, stays as it is. Returns,
// per vertex of the new mesh, the vertex it was (the identity when there are none); reported.
std::vector<uint32_t> weldExactCopies(SkinnedMesh &mesh, Reporter &reporter,
                                      const std::vector<uint32_t> &keep = {});

// Flat shading: a low-poly model exported flat-shaded gives each triangle corner its own vertex,
// its normal the face's, so every edge is a normal seam and nothing collapses. Faceted vertices
// (the normal their face's within `maxAngleDeg` in every triangle using them) that differ only by
// their normal weld into one; in a sub-mesh where any do, every faceted vertex's normal (and its
// morph normals) is stored as zero: the player, the CPU mirror and the impostor bake shade it
// with its face's normal, the same at full detail. Returns, per vertex of the new mesh, the
// vertex it was (the identity when nothing is flat-shaded); reported. `keep` (optional): vertices
// never welded nor changed (a cloth loop's: the pack places them by their glTF source).
std::vector<uint32_t> weldFlatShading(SkinnedMesh &mesh, Reporter &reporter, double maxAngleDeg = 1,
                                      const std::vector<uint32_t> &keep = {});

// The same arrays, applied to a character (exact copies and flat shading welded first): its mesh
// reordered (vertices, and triangles within each sub-mesh) and the pack's LOD chunk for it.
pack::Lod applyLod(Character &character, const LodOptions &options, Reporter &reporter,
                   LodResult *details = nullptr, const std::vector<uint32_t> &keep = {});

// Seams are where input vertices share a position but not their other attributes (UV, normal):
// such copies weld into one topological vertex, unless `group` (per vertex, optional) differs.
// `positions`: the rest pose, in the poses' units (applyLod gives the character as drawn without
// a clip). `poses` (optional): the vertices skinned into other poses; a collapse then costs its
// quadric error in the worst of the rest pose and every pose, so the order suits the animation,
// not just the rest. `appearance` (optional, per input vertex): hard edges may close within
// options.seamBudget; without it every seam holds.
LodResult bakeLod(const std::vector<glm::vec3> &positions, const std::vector<uint32_t> &indices,
                  const LodOptions &options, Reporter &reporter,
                  const std::vector<uint32_t> &group = {},
                  const std::vector<std::vector<glm::vec3>> &poses = {},
                  const LodAppearance *appearance = nullptr);

} // namespace crowd
