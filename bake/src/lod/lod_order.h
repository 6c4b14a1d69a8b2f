// bakeLod's output: the collapses' record turned into the pack's order of vertices and
// triangles (LodResult).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "collapse_loop.h"
#include "crowd/bake/lod_bake.h"

namespace crowd::lod {

// Vertices never removed first (input order), then the removed ones, last removed first; render
// vertices no face uses go last, into vertex 0. Fills r.order, floorVertices, collapse and error;
// returns each render vertex's new index. `isolated`: how many of those last the input's
// triangles do not use at all.
std::vector<uint32_t> numberVertices(const FanMesh &fan, const Removals &removals,
                                     const std::vector<uint32_t> &indices, LodResult &r,
                                     size_t &isolated);

// Triangles that survive to the floor first, then the rest, last deleted first, each with the
// input's corners and winding (`initialCorner`, in render vertices). Fills r.indices,
// triangleCount, source and killedBy.
void orderTriangles(const FanMesh &fan, const std::vector<std::array<uint32_t, 3>> &initialCorner,
                    const Removals &removals, const std::vector<uint32_t> &newIndex, LodResult &r);

} // namespace crowd::lod
