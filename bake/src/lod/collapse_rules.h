// Whether a may collapse into b, and where a refusal of that collapse is kept. A seam or boundary
// vertex slides only along its line, or leaves a hard edge within the seam budget; the link
// condition keeps the mesh manifold; no face left turns more than the limit from its full-detail
// normal, flips or loses its area.
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "collapse_mesh.h"
#include "refusals.h"

namespace crowd::lod {

class CollapseRules {
public:
  CollapseRules(const CollapseMesh &mesh, double maxNormalDeviationDeg);
  // Why a may not collapse into b (Block::kNone: it may); `edge`: the edge's live faces, which
  // the collapse then takes. Leaves a's ring in ringA and, past the seam test, b's in ringB.
  Block check(uint32_t a, uint32_t b, EdgeFaces &edge);
  // The Refusals slot of the collapse of a into b, an edge of the faces `edge` (in either order).
  Refusals::Slot slotOf(uint32_t a, uint32_t b, const EdgeFaces &edge) const;
  Ring ringA, ringB;
  std::vector<uint32_t> renderA, renderB; // closes(): a's and b's render vertices
  // Past a check that closes a hard edge: each render vertex of a on no face of the edge, with
  // the render vertex of b its corners are drawn with from then on (empty: none closes).
  std::vector<std::pair<uint32_t, uint32_t>> closing;

private:
  Block seam(uint32_t a, uint32_t b, const EdgeFaces &edge);
  bool closes(uint32_t a, uint32_t b, const EdgeFaces &edge);
  Block link(uint32_t a, uint32_t b, const EdgeFaces &edge, uint32_t apex[2]) const;
  Block normals(uint32_t a, uint32_t b, const EdgeFaces &edge, const uint32_t apex[2]) const;
  const CollapseMesh &mesh_;
  double cosLimit_;
};

} // namespace crowd::lod
