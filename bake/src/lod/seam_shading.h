// Seams that may close: a hard edge (two render vertices at one vertex that differ in their
// normal alone) is drawn as a jump in shading. A collapse that takes such a vertex off its seam
// draws the faces on the far side with the near side's normal at that corner, which changes what
// the player draws; it may, by no more than the appearance budget. The change is bounded under
// the player's light (crowd.frag: albedo x (0.25 + 0.75 max(n.l, 0)), any light direction l):
// 255 x 0.75 x |albedo| x |n - n'| in 8-bit RGB. The jumps a corner's normal takes across hard
// edges are summed along its chain of closings, so the budget holds for them against the
// full-detail mesh at every level; a collapse along a surface changes normals as it always did,
// weighed by its geometric cost, not here. The albedo is the material's: a scene palette that
// recolours a region brighter scales the change with it.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/bake/lod_bake.h"

namespace crowd::lod {

class SeamShading {
public:
  SeamShading() = default; // nothing given: no seam closes
  // `appearance`: per input vertex; `source`: per render vertex, its input vertex.
  SeamShading(const LodAppearance &appearance, const std::vector<uint32_t> &source, double budget);
  bool active() const { return budget_ > 0 && !normal_.empty(); }
  // Render vertices r and s at one vertex differ in their normal alone (their UVs agree, or their
  // sub-mesh is untextured): a seam between them is a hard edge, which may close.
  bool normalOnly(uint32_t r, uint32_t s) const { return key_[r] == key_[s]; }
  // The colour change, 8-bit RGB, where the corners r stands for are drawn with s instead.
  double change(uint32_t r, uint32_t s) const { return scale_[r] * (moved_[r] + jump(r, s)); }
  bool within(double change) const { return change <= budget_; }
  // r's corners are drawn with s from now on: across the seam (closed: returns the colour change
  // that makes) or along it.
  double closed(uint32_t r, uint32_t s);
  void carried(uint32_t r, uint32_t s);
  size_t closings() const { return closings_; }
  double largestChange() const { return largest_; }

private:
  double jump(uint32_t r, uint32_t s) const; // |n_r - n_s|; 2 where one is shaded by its face
  std::vector<glm::vec3> normal_;
  std::vector<float> scale_;  // per render vertex: 255 x 0.75 x |albedo|
  std::vector<float> moved_;  // per render vertex: the normal change its corners already carry
  std::vector<uint32_t> key_; // per render vertex
  double budget_ = 0, largest_ = 0;
  size_t closings_ = 0;
};

} // namespace crowd::lod
