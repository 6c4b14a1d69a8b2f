// Welding a skinned mesh's vertices into others (exact_copies.cpp, flat_shading.cpp): the key that
// finds copies, and the weld itself.
#pragma once
#include <cstdint>
#include <vector>

#include "crowd/bake/character.h"

namespace crowd::lod {

// Vertex v's attributes as exact bits, after `part` (its sub-mesh): position, UV, skin, morph
// offsets, and with `normals` its normal and its morphs' normals. Equal keys: copies.
std::vector<uint32_t> vertexKey(const SkinnedMesh &m, uint32_t v, uint32_t part, bool normals);

// Welds each vertex v into into[v] (into[v] <= v, and into[into[v]] == into[v]): the triangles
// are renumbered onto the vertices that stay, which keep their input order and every attribute.
// Returns, per vertex of the new mesh, the vertex it was.
std::vector<uint32_t> weldInto(SkinnedMesh &m, const std::vector<uint32_t> &into);

} // namespace crowd::lod
