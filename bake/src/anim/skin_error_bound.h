// How far, at most, a vertex skinned as the player skins it (single precision, joint rows sampled
// from a texture: runtime::skinVertex) lies from the same vertex skinned exactly (double
// precision, the exact joint matrices: skinPosition), from the joints' errors alone: the bake's
// error budget measures the largest error over every vertex at each time it tries, and a vertex
// or a block of vertices whose bound is below the largest found so far cannot change it.
//
// The bound of vertex p with influences (w_k, joint j_k): sum_k |w_k| (|A_j| |p - c_j| + |E_j c1|
// + 16 eps (|R_j| |p| + |t_j|)), where R_j is joint j's sampled 3x3 part and t_j its translation,
// E_j their difference from its exact matrix's (3x4), A_j E_j's 3x3 part (Frobenius norms:
// |A x| <= |A|_F |x|), c_j the weighted centre of the vertices j moves and c1 = (c_j, 1):
// E_j (p, 1) = A_j (p - c_j) + E_j c1. 16 eps (|R_j| |p| + |t_j|) covers the rounding of the
// single-precision sum (each row's dot product and the weighted sum round within 9 units in the
// last place of the sum of their terms' sizes, which a row r, t holds to |r| |p| + |t|) and,
// with room to spare, of the double one. (With |(p, 1)| in place of |p| and the translation in
// R_j, gltfpack's quantized positions, in the thousands, left 91% of the vertices to skin.)
//
// With morph targets the player skins p' (its morph slots, weights blended between frames), the
// exact skinning p: the error is sum_k w_k (E_j (p', 1) + M_j (p' - p)), M_j the exact matrix's
// 3x3 part, so p' takes p's place above and each influence adds |M_j| |p' - p|. Blocks are not
// bounded then (the caller works out p' and p vertex by vertex): blocks() is false.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/bake/character.h"
#include "crowd/formats/chunks.h"
#include "crowd/runtime/texture_skinning.h"

namespace crowd {

class SkinErrorBound {
public:
  static constexpr uint32_t kBlock = 32; // vertices a block
  // Per joint at one time: |A_j|, |E_j c1| + 16 eps |t_j|, 16 eps |R_j| and |M_j|.
  using Terms = std::vector<std::array<double, 4>>;

  SkinErrorBound(const SkinnedMesh &m, const pack::SkinTexture &skin, size_t jointCount);
  // The terms of joint rows `rows` against the exact matrices `exact` (one per joint).
  Terms terms(const std::vector<runtime::JointRows> &rows,
              const std::vector<glm::dmat4> &exact) const;
  // The bound of vertex v, and one of every vertex in block b (vertices b kBlock on), squared.
  double vertex(uint32_t v, const Terms &t) const;
  bool blocks() const { return !blockStart_.empty(); } // false for a mesh with morph targets
  double block(uint32_t b, const Terms &t) const;
  // The bound of vertex v, squared, where the player skins `drawn` and the exact skinning
  // `exact` (their morphed positions).
  double morphedVertex(uint32_t v, const Terms &t, const glm::dvec3 &drawn,
                       const glm::dvec3 &exact) const;

private:
  // The bound of vertex v, squared, with `apart` its influences' |p - c_j|, `reach` |p| and
  // `morphOff` |p' - p|.
  double sum(uint32_t v, const Terms &t, const double *apart, double reach, double morphOff) const;
  // Per joint a block's vertices use: the largest over them of its three terms' factors (the
  // sum of the vertex's weights on the joint times their distances to c_j, of its weights, and
  // of its weights times |p|).
  struct BlockTerm {
    uint32_t joint;
    double apart, weight, reach;
  };
  const pack::SkinTexture &skin_;
  std::vector<glm::dvec3> centre_; // per joint
  std::vector<double> apart_;      // per vertex and influence: |p - c_j|
  std::vector<double> reach_;      // per vertex: |p|
  std::vector<size_t> blockStart_; // into blockTerms_, per block and one past the last; or empty
  std::vector<BlockTerm> blockTerms_;
};

} // namespace crowd
