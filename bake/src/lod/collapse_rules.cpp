#include "collapse_rules.h"

#include <algorithm>
#include <cmath>

namespace crowd::lod {

CollapseRules::CollapseRules(const CollapseMesh &mesh, double maxNormalDeviationDeg)
    : ringA(mesh.vertices()), ringB(mesh.vertices()), mesh_(mesh),
      cosLimit_(std::cos(maxNormalDeviationDeg * 3.14159265358979323846 / 180)) {}

Block CollapseRules::check(uint32_t a, uint32_t b, EdgeFaces &edge) {
  mesh_.ringOf(a, ringA);
  const Neighbour *n = ringA.find(b);
  if (!n)
    return Block::kNoEdge; // no longer an edge
  edge.sides = std::min(n->faces, 2u), edge.face[0] = n->first, edge.face[1] = n->second;
  if (const Block why = seam(a, b, edge); why != Block::kNone)
    return why;
  mesh_.ringOf(b, ringB); // only past the seam test: of Fox's 994 checks, 625 stop there
  uint32_t apex[2] = {UINT32_MAX, UINT32_MAX};
  if (const Block why = link(a, b, edge, apex); why != Block::kNone)
    return why;
  return normals(a, b, edge, apex);
}

// A seam or boundary vertex a slides only along its line: exactly two special edges, and the
// one to b of them; or it closes its hard edges (closes()).
Block CollapseRules::seam(uint32_t a, uint32_t b, const EdgeFaces &edge) {
  closing.clear();
  int specials = 0;
  bool along = false;
  for (const Neighbour &n : ringA.around)
    if (n.special) {
      ++specials;
      along |= n.v == b;
    }
  if (specials == 0 || (specials == 2 && along))
    return Block::kNone;
  return closes(a, b, edge) ? Block::kNone : Block::kSeam;
}

// a's seams are all hard edges (no open edge; its render vertices, and b's, differ in their
// normal alone), and each render vertex of a on no face of the edge has one of b's whose normal
// keeps the colour change within the budget: the nearest such normal is taken. Where every render
// vertex of a lies on the edge's faces (a seam's end, or where two seam lines meet), none
// closes: each face keeps its side's attributes, and only the seam's shape moves, at the cost
// of its border planes (CollapseMesh::fillBorderQuadrics).
bool CollapseRules::closes(uint32_t a, uint32_t b, const EdgeFaces &edge) {
  const SeamShading &shading = mesh_.shading;
  if (!shading.active())
    return false;
  for (const Neighbour &n : ringA.around)
    if (n.faces == 1)
      return false; // a boundary holds its shape
  mesh_.renderVerticesOf(a, renderA);
  mesh_.renderVerticesOf(b, renderB);
  for (const auto *rs : {&renderA, &renderB})
    for (uint32_t r : *rs)
      if (!shading.normalOnly(r, rs->front()))
        return false; // a UV seam: the far side's faces would sample another island
  for (uint32_t ra : renderA) {
    bool paired = false;
    for (uint32_t s = 0; s < edge.sides; ++s)
      paired |= mesh_.fan.render[edge.face[s]][mesh_.corner(edge.face[s], a)] == ra;
    if (paired)
      continue;
    uint32_t best = UINT32_MAX;
    double least = 0;
    for (uint32_t rb : renderB)
      if (const double c = shading.change(ra, rb); best == UINT32_MAX || c < least)
        best = rb, least = c;
    if (best == UINT32_MAX || !shading.within(least))
      return false;
    closing.emplace_back(ra, best);
  }
  return true;
}

// The link condition: the vertices next to both ends are exactly the faces' apexes (which are
// always next to both: the count says whether there are others), so the mesh stays manifold; an
// inner edge joining two boundary vertices would pinch it. Fills `apex`, the faces' third corners.
Block CollapseRules::link(uint32_t a, uint32_t b, const EdgeFaces &edge, uint32_t apex[2]) const {
  for (uint32_t s = 0; s < edge.sides; ++s)
    for (uint32_t w : mesh_.fan.vertex[edge.face[s]])
      if (w != a && w != b)
        apex[s] = w;
  uint32_t common = 0;
  for (const Neighbour &n : ringA.around)
    common += ringB.count(n.v) != 0;
  if (common != edge.sides)
    return Block::kManifold;
  auto onBoundary = [](const Ring &ring) {
    for (const Neighbour &n : ring.around)
      if (n.faces == 1)
        return true;
    return false;
  };
  if (edge.sides == 2 && onBoundary(ringA) && onBoundary(ringB))
    return Block::kManifold;
  for (uint32_t s = 0; s < edge.sides; ++s) // a face with two open edges would leave a dangling one
    if (ringA.count(apex[s]) == 1 && ringB.count(apex[s]) == 1)
      return Block::kManifold;
  return Block::kNone;
}

// Each face of a that stays, with a moved to b: not a tetrahedron's double face, not without
// area, not flipped, not turned past the limit.
Block CollapseRules::normals(uint32_t a, uint32_t b, const EdgeFaces &edge,
                             const uint32_t apex[2]) const {
  const glm::dvec3 target = mesh_.rest(b);
  for (uint32_t f : mesh_.facesOf[a]) {
    if (!mesh_.alive[f] || mesh_.has(f, b))
      continue; // this face disappears
    // A tetrahedron: the faces left would be one triangle twice. Stricter than that: a face of
    // a holds both apexes whenever a has valence 3, so such a vertex inside a surface never
    // goes; the exact test (only where b also has a face on both apexes) moved the animated
    // error both ways, and waits for a less tie-sensitive order.
    if (edge.sides == 2 && mesh_.has(f, apex[0]) && mesh_.has(f, apex[1]))
      return Block::kManifold;
    const std::array<uint32_t, 3> &fv = mesh_.fan.vertex[f];
    const glm::dvec3 before = mesh_.normalOf(fv);
    glm::dvec3 p[3];
    for (int k = 0; k < 3; ++k)
      p[k] = fv[size_t(k)] == a ? target : mesh_.rest(fv[size_t(k)]);
    const glm::dvec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
    const double len = glm::length(n);
    if (len <= 1e-12 * glm::dot(target, target) + 1e-30)
      return Block::kNormal;
    if (glm::dot(n / len, mesh_.originalNormal[f]) < cosLimit_ || glm::dot(n, before) <= 0)
      return Block::kNormal;
  }
  return Block::kNone;
}

Refusals::Slot CollapseRules::slotOf(uint32_t a, uint32_t b, const EdgeFaces &edge) const {
  for (uint32_t s = 0; s < edge.sides; ++s)
    if (const uint32_t f = edge.face[s], e = mesh_.corner(f, a);
        mesh_.fan.vertex[f][(e + 1) % 3] == b)
      return {3 * size_t(f) + e, false}; // the face winding a -> b
  return {3 * size_t(edge.face[0]) + mesh_.corner(edge.face[0], b),
          true}; // an open edge's other way
}

} // namespace crowd::lod
