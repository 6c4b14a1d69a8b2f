// The mesh as bakeLod's collapses change it: the fan mesh's faces (their corners move from the
// vertex that goes to the one it goes into), which faces still live, each vertex's faces, the
// pose quadrics, and which edges are open or seams. Built in named stages (fillFaceLists,
// fillFaceQuadrics, markSpecialEdges, fillBorderQuadrics); the rest pose never moves.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "face_lists.h"
#include "fan_mesh.h"
#include "pose_quadrics.h"
#include "seam_shading.h"

namespace crowd::lod {

// A vertex's neighbour w: the live faces it shares with the vertex (1: an open edge between
// them), the first two of them in the vertex's list and the render vertices of both ends in the
// first; `special` once the ring is built: the edge is open, or a seam (the first two faces use
// other render vertices for an end).
struct Neighbour {
  uint32_t v, faces, first, second, renderSelf, renderOther;
  bool special;
};

// A vertex's neighbours in the order its faces first reach them, with each one's place in
// `around` (1 + its index; 0: not a neighbour): a lookup a corner, not a search of `around`.
class Ring {
public:
  explicit Ring(size_t vertices) : slot_(vertices, 0) {}
  std::vector<Neighbour> around;
  void clear() {
    for (const Neighbour &n : around)
      slot_[n.v] = 0;
    around.clear();
  }
  Neighbour *find(uint32_t w) { return slot_[w] ? &around[slot_[w] - 1] : nullptr; }
  void add(const Neighbour &n) {
    around.push_back(n);
    slot_[n.v] = uint32_t(around.size());
  }
  uint32_t count(uint32_t w) const { return slot_[w] ? around[slot_[w] - 1].faces : 0; }

private:
  std::vector<uint32_t> slot_;
};

// An edge's live faces (at most two: the mesh stays manifold).
struct EdgeFaces {
  uint32_t face[2] = {UINT32_MAX, UINT32_MAX};
  uint32_t sides = 0;
};

class CollapseMesh {
public:
  // `poses`: per pose, every input vertex's position (PoseQuadrics).
  CollapseMesh(FanMesh fan, const std::vector<std::vector<glm::vec3>> &poses);
  CollapseMesh(const CollapseMesh &) = delete; // the quadrics read fan's arrays

  FanMesh fan;                            // vertex and render change as the collapses go
  PoseQuadrics quadric;                   // one per vertex per pose
  FaceLists facesOf;                      // each vertex's faces, live or not
  std::vector<uint8_t> alive;             // per face
  size_t aliveFaces;                      // how many
  std::vector<glm::dvec3> originalNormal; // per face, in the rest pose at full detail
  // Per face, a bit for each of its open (special: open or seam) edges, from corner e to e + 1,
  // as the mesh was built.
  std::vector<uint8_t> open, special;
  SeamShading shading; // which hard edges may close (none unless set)

  size_t vertices() const { return fan.position.size(); }
  size_t faces() const { return fan.vertex.size(); }
  const glm::dvec3 &rest(uint32_t v) const { return fan.position[v]; }
  uint32_t corner(uint32_t f, uint32_t v) const {
    const auto &fv = fan.vertex[f];
    return fv[0] == v ? 0 : fv[1] == v ? 1 : 2;
  }
  bool has(uint32_t f, uint32_t v) const {
    const auto &fv = fan.vertex[f];
    return fv[0] == v || fv[1] == v || fv[2] == v;
  }
  glm::dvec3 normalOf(const std::array<uint32_t, 3> &f) const; // in the rest pose, not unit
  EdgeFaces edgeFaces(uint32_t a, uint32_t b) const;
  // v's neighbours, each edge to them open or a seam or neither, from one pass over v's faces.
  void ringOf(uint32_t v, Ring &ring) const;
  // v's render vertices in its live faces, each once, in the order its faces list them.
  void renderVerticesOf(uint32_t v, std::vector<uint32_t> &out) const;

private:
  void fillFaceLists();
  void fillFaceQuadrics();
  void markSpecialEdges();
  void fillBorderQuadrics();
};

} // namespace crowd::lod
