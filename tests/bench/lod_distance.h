// How far a LOD's surface is from the full mesh, as lod_bench reports it: the symmetric Hausdorff
// distance in the rest pose the player draws (posedPositions with no clip) and at every frame of
// every clip, as % of the rest pose's bounding-box diagonal (restDiagonal). Both poses are the
// skinned ones: a mesh stored in other units than its skin brings it to (an armature scale) or
// rigid parts stored in their node's frame are measured where they are drawn.
// Hausdorff: points sampled on each surface (every corner, plus area-uniform samples from a fixed
// seed) against a CGAL AABB tree of the other's triangles, both ways; the estimate of CGAL's
// approximate_Hausdorff_distance, but over triangle soups, which LOD cuts and meshopt's output
// may be (non-manifold), where a Surface_mesh could not be built.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/bake/character.h"
#include "crowd/bake/lod_bake.h"

namespace crowd::bench {

struct LodDistance {
  double restPct = 0.0;        // in the rest pose
  double animatedMaxPct = 0.0; // the largest over every frame
  double animatedMeanPct = 0.0;
};

class LodDistanceMeasure {
public:
  // Poses the character at rest and at every clip's frames at `fps` (at rest only, without
  // clips); `samples` area samples per surface and direction.
  LodDistanceMeasure(const Character &c, double fps = 30.0, int samples = 4000);
  // `lod`: triangles as indices into the character's vertices.
  LodDistance measure(const std::vector<uint32_t> &lod) const;
  const std::vector<glm::dvec3> &rest() const { return rest_; }
  double diagonal() const { return diagonal_; }
  size_t frameCount() const { return frames_.size(); }

private:
  const Character &c_;
  int samples_;
  double diagonal_;
  std::vector<glm::dvec3> rest_;
  std::vector<std::vector<glm::dvec3>> frames_;
};

// One character as the LOD benchmarks collapse it, as crowdbake lod does: imported, exact copies
// and flat shading welded (applyLod), the triangles and groups it collapses, its sampled poses
// and its rest pose as the player draws it (and as LodDistanceMeasure poses it).
struct LodInput {
  Character character;
  LodTriangles triangles;
  std::vector<std::vector<glm::vec3>> poses;
  std::vector<glm::vec3> rest;
  LodAppearance appearance; // what the seam budget weighs, as applyLod gives it
};
LodInput loadLodInput(const char *path, Reporter &reporter);

// A LOD's cut at the fewest vertices holding `triangles` (its floor where it stops above), as
// triangles on the input vertices: what measure() takes.
std::vector<uint32_t> lodCut(const LodResult &r, size_t triangles);

} // namespace crowd::bench
