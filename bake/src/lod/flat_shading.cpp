#include <cmath>

#include "crowd/bake/character.h"
#include "crowd/bake/lod_bake.h"
#include "vertex_weld.h"

namespace crowd {

std::vector<uint32_t> weldFlatShading(SkinnedMesh &m, Reporter &reporter, double maxAngleDeg,
                                      const std::vector<uint32_t> &keep) {
  const size_t V = m.positions.size(), T = m.indices.size() / 3;
  std::vector<uint32_t> kept(V);
  for (uint32_t v = 0; v < V; ++v)
    kept[v] = v;
  // A vertex is faceted when, in every triangle using it, its normal is that face's; and it
  // lies in one sub-mesh only. Either way round: under a mirroring node the triangles are stored
  // turned to face out as drawn (the importer), so in the mesh's own frame they face in.
  const double cosLimit = std::cos(maxAngleDeg * 3.14159265358979323846 / 180);
  const std::vector<uint32_t> partOf = triangleParts(m);
  std::vector<uint8_t> faceted(V, 0); // 0 unused, 1 faceted so far, 2 not
  std::vector<uint32_t> partOfVertex(V, 0);
  for (size_t t = 0; t < T; ++t) {
    const uint32_t *c = &m.indices[3 * t];
    const glm::dvec3 a(m.positions[c[0]]), b(m.positions[c[1]]), d(m.positions[c[2]]);
    glm::dvec3 face = glm::cross(b - a, d - a);
    const double len = glm::length(face);
    if (len == 0)
      continue; // no face normal: it says nothing of its corners' shading
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = c[k];
      const glm::dvec3 n(m.normals[v]);
      const bool flat =
          glm::length(n) > 0 && std::abs(glm::dot(n / glm::length(n), face / len)) >= cosLimit;
      if (faceted[v] != 0 && partOfVertex[v] != partOf[t])
        faceted[v] = 2;
      partOfVertex[v] = partOf[t];
      faceted[v] = flat && faceted[v] != 2 ? 1 : 2;
    }
  }
  for (uint32_t v : keep)
    if (v < V)
      faceted[v] = 2;
  // Faceted vertices differing only by their normal (same sub-mesh, position, skin, morph offsets
  // and, where the sub-mesh is textured, UV) weld into their first. A sub-mesh where any do is
  // flat-shaded: all its faceted vertices are then shaded by their faces. A smooth mesh's planar
  // patch is left as it is.
  lod::CopyFinder finder(m, false); // every attribute but the normal
  std::vector<uint8_t> flatPart(m.parts.size() + 1, 0), byFace(V, 0);
  for (uint32_t v = 0; v < V; ++v)
    if (faceted[v] == 1) {
      kept[v] = finder.firstOf(v, partOfVertex[v]);
      flatPart[partOfVertex[v]] |= kept[v] != v;
    }
  size_t shaded = 0;
  for (uint32_t v = 0; v < V; ++v) {
    if (faceted[v] == 1 && !flatPart[partOfVertex[v]])
      kept[v] = v; // a sub-mesh with no copy to weld keeps its normals
    else if (faceted[v] == 1)
      byFace[v] = 1, ++shaded;
  }
  if (shaded == 0)
    return kept;

  // Keep the first of each weld, in input order; its normal (and its morphs' normals) zero.
  const std::vector<uint32_t> from = lod::weldInto(m, kept);
  for (uint32_t k = 0; k < from.size(); ++k)
    if (byFace[from[k]]) {
      m.normals[k] = glm::vec3(0.0f);
      for (auto &target : m.morphs)
        target.normals[k] = glm::vec3(0.0f);
    }
  reporter.warn("flat_shaded",
                std::to_string(shaded) + " vertices are flat-shaded (each normal its face's): " +
                    std::to_string(V - from.size()) +
                    " copies that differed only by their normal welded, so the LOD can collapse "
                    "them; they are drawn with their face's normal (stored as zero)",
                shaded);
  return from;
}

} // namespace crowd
