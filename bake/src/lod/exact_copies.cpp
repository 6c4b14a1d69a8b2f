#include "crowd/bake/character.h"
#include "crowd/bake/lod_bake.h"
#include "vertex_weld.h"

namespace crowd {

std::vector<uint32_t> weldExactCopies(SkinnedMesh &m, Reporter &reporter,
                                      const std::vector<uint32_t> &keep) {
  const size_t V = m.positions.size();
  // Each vertex's sub-mesh; kNone where unused, kMixed where two sub-meshes use it (not welded:
  // sub-meshes keep their own borders, as lodTriangles welds them).
  constexpr uint32_t kNone = UINT32_MAX, kMixed = UINT32_MAX - 1;
  const std::vector<uint32_t> partOf = triangleParts(m);
  std::vector<uint32_t> part(V, kNone);
  for (size_t i = 0; i < m.indices.size(); ++i) {
    uint32_t &p = part[m.indices[i]];
    p = p == kNone || p == partOf[i / 3] ? partOf[i / 3] : kMixed;
  }
  for (uint32_t v : keep)
    if (v < V)
      part[v] = kMixed;
  lod::CopyFinder finder(m, true);
  std::vector<uint32_t> into(V);
  size_t copies = 0, uvOnly = 0; // uvOnly: copies whose UV differs (an untextured sub-mesh)
  for (uint32_t v = 0; v < V; ++v) {
    into[v] = v;
    if (part[v] == kNone || part[v] == kMixed)
      continue;
    into[v] = finder.firstOf(v, part[v]);
    copies += into[v] != v;
    uvOnly += into[v] != v && !m.uvs.empty() && m.uvs[v] != m.uvs[into[v]];
  }
  if (copies == 0)
    return into; // the identity

  const std::vector<uint32_t> was = lod::weldInto(m, into);
  reporter.warn("exact_copies",
                std::to_string(copies) +
                    " vertices repeat another exactly (every attribute the same, as a mesh "
                    "written without shared vertices has them): welded, so the LOD can collapse "
                    "across them; the drawn mesh is the same" +
                    (uvOnly ? " (" + std::to_string(uvOnly) +
                                  " of them differ in their UVs alone, in an untextured sub-mesh, "
                                  "which draws its material's colour whatever its UVs)"
                            : std::string()),
                copies);
  return was;
}

} // namespace crowd
