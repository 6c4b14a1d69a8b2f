// Welding a skinned mesh's vertices into others (exact_copies.cpp, flat_shading.cpp): finding
// copies, and the weld itself.
#pragma once
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "crowd/bake/character.h"

namespace crowd::lod {

// Finds each vertex's first copy: the first vertex asked about with the same sub-mesh and the
// same attributes, as exact bits (-0 as +0): position, UV (where the sub-mesh is textured: an
// untextured one draws its material's colour whatever its UVs), skin, morph offsets, and with
// `normals` its normal and its morphs' normals. Hashed, comparing the attributes themselves on a
// hash match, with no allocation per vertex: a std::map of per-vertex key vectors took 3.4 s
// for a 1M-triangle grid written without indices.
class CopyFinder {
public:
  CopyFinder(const SkinnedMesh &m, bool normals) : m_(m), normals_(normals) {}
  // The first vertex asked about that v copies, or v itself (from now on the first).
  uint32_t firstOf(uint32_t v, uint32_t part);

private:
  void key(uint32_t v, uint32_t part, std::vector<uint32_t> &out) const;
  const SkinnedMesh &m_;
  bool normals_;
  std::unordered_multimap<uint64_t, std::pair<uint32_t, uint32_t>> firsts_; // hash: vertex, part
  std::vector<uint32_t> key_, other_;                                       // reused
};

// Welds each vertex v into into[v] (into[v] <= v, and into[into[v]] == into[v]): the triangles
// are renumbered onto the vertices that stay, which keep their input order and every attribute.
// Returns, per vertex of the new mesh, the vertex it was.
std::vector<uint32_t> weldInto(SkinnedMesh &m, const std::vector<uint32_t> &into);

} // namespace crowd::lod
