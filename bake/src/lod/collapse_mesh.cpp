#include "collapse_mesh.h"

#include <algorithm>

namespace crowd::lod {
namespace {

std::vector<uint32_t> valences(const FanMesh &fan) {
  std::vector<uint32_t> valence(fan.position.size(), 0);
  for (const auto &fv : fan.vertex)
    for (uint32_t v : fv)
      ++valence[v];
  return valence;
}

} // namespace

CollapseMesh::CollapseMesh(FanMesh fanMesh, const std::vector<std::vector<glm::vec3>> &poses)
    : fan(std::move(fanMesh)), quadric(fan.position, poses, fan.inputOf), facesOf(valences(fan)),
      alive(fan.vertex.size(), 1), aliveFaces(fan.vertex.size()), originalNormal(fan.vertex.size()),
      open(fan.vertex.size(), 0), special(fan.vertex.size(), 0) {
  fillFaceLists();
  fillFaceQuadrics();
  markSpecialEdges();
  fillBorderQuadrics();
  quadric.finish();
}

glm::dvec3 CollapseMesh::normalOf(const std::array<uint32_t, 3> &f) const {
  const glm::dvec3 &a = rest(f[0]);
  return glm::cross(rest(f[1]) - a, rest(f[2]) - a);
}

EdgeFaces CollapseMesh::edgeFaces(uint32_t a, uint32_t b) const {
  EdgeFaces edge;
  for (uint32_t f : facesOf[a])
    if (alive[f] && has(f, b) && edge.sides < 2)
      edge.face[edge.sides++] = f;
  return edge;
}

void CollapseMesh::ringOf(uint32_t v, Ring &ring) const {
  ring.clear();
  for (uint32_t f : facesOf[v]) {
    if (!alive[f])
      continue;
    const uint32_t self = fan.render[f][corner(f, v)];
    for (uint32_t k = 0; k < 3; ++k) {
      const uint32_t w = fan.vertex[f][k];
      if (w == v)
        continue;
      if (Neighbour *n = ring.find(w); !n)
        ring.add({w, 1, f, UINT32_MAX, self, fan.render[f][k], false});
      else if (++n->faces == 2)
        n->second = f, n->special = n->renderSelf != self || n->renderOther != fan.render[f][k];
    }
  }
  for (Neighbour &n : ring.around)
    n.special |= n.faces == 1;
}

void CollapseMesh::renderVerticesOf(uint32_t v, std::vector<uint32_t> &out) const {
  out.clear();
  for (uint32_t f : facesOf[v])
    if (alive[f])
      if (const uint32_t r = fan.render[f][corner(f, v)];
          std::find(out.begin(), out.end(), r) == out.end())
        out.push_back(r);
}

void CollapseMesh::fillFaceLists() {
  for (uint32_t f = 0; f < faces(); ++f) {
    originalNormal[f] = glm::normalize(normalOf(fan.vertex[f]));
    for (uint32_t v : fan.vertex[f])
      facesOf.push(v, f);
  }
}

// A collapse costs what it moves the surface in every pose, each measured where the vertex is
// in that pose; the rest of the bake (normals, legality) looks at the rest pose alone.
void CollapseMesh::fillFaceQuadrics() {
  for (const auto &fv : fan.vertex)
    quadric.addFace(fv);
}

// Each vertex's ring says which of its edges are open or seams (one pass a vertex, not an
// edgeFaces search an edge); each such edge is marked in its first face (facesOf lists ascend).
void CollapseMesh::markSpecialEdges() {
  Ring ring(vertices());
  for (uint32_t v = 0; v < vertices(); ++v) {
    ringOf(v, ring);
    for (const Neighbour &n : ring.around) {
      if (!n.special)
        continue;
      const uint32_t f = n.first, cv = corner(f, v), cw = corner(f, n.v);
      const uint32_t e = cw == (cv + 1) % 3 ? cv : cw;
      special[f] |= uint8_t(1u << e);
      open[f] |= uint8_t(n.faces == 1) << e;
    }
  }
}

// Boundaries and seams hold their shape: each special edge adds, to both ends, a plane through
// it, perpendicular to its face (PoseQuadrics::addBorder), face by face so that every quadric
// sums them in one order.
void CollapseMesh::fillBorderQuadrics() {
  for (uint32_t f = 0; f < faces(); ++f)
    for (uint32_t e = 0; e < 3; ++e)
      if (special[f] >> e & 1)
        quadric.addBorder(fan.vertex[f][e], fan.vertex[f][(e + 1) % 3], fan.vertex[f][(e + 2) % 3]);
}

} // namespace crowd::lod
