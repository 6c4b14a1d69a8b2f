// bakeLod's collapse loop: cheapest collapse first (CostQueue, costs from the pose quadrics),
// each checked by CollapseRules when it comes up, until the floor or until a pass over every
// remaining edge finds none legal.
#pragma once
#include <cstdint>
#include <vector>

#include "collapse_mesh.h"
#include "collapse_rules.h"
#include "refusals.h"

namespace crowd::lod {

// What the collapses did, in render vertices: who went, in order, into whom, at what cost and
// what colour change (a hard edge's closing, 8-bit RGB; 0: none); and for each face the render
// vertex whose removal deleted it (-1: it lasts).
struct Removals {
  std::vector<uint32_t> removed, target;
  std::vector<float> cost, colour;
  std::vector<int64_t> killer;
};

Removals collapseToFloor(CollapseMesh &mesh, CollapseRules &rules, Refusals &refusals,
                         size_t floorFaces);

} // namespace crowd::lod
