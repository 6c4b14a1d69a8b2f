#include "crowd/bake/lod_bake.h"

#include <cmath>
#include <cstdio>

#include "collapse_loop.h"
#include "collapse_mesh.h"
#include "collapse_rules.h"
#include "crowd/formats/error.h"
#include "fan_mesh.h"
#include "lod_order.h"
#include "refusals.h"

// By hand on flat arrays, not OpenMesh's half-edge collapse (about twice as fast here), and not
// meshoptimizer's simplifier, which returns index buffers at given counts, not the order of
// every collapse with its cost that the pack stores.
namespace crowd {
namespace {

void checkInput(const std::vector<glm::vec3> &positions, const std::vector<uint32_t> &indices,
                const std::vector<std::vector<glm::vec3>> &poses) {
  for (const auto &pose : poses)
    if (pose.size() != positions.size())
      throw Error("lod: a pose has another vertex count than the mesh");
  if (indices.size() % 3 != 0)
    throw Error("lod: the index count is not a multiple of 3");
  for (uint32_t i : indices)
    if (i >= positions.size())
      throw Error("lod: an index points past the vertices");
}

void reportRepairs(const lod::FanMesh &m, Reporter &reporter) {
  if (m.degenerate)
    reporter.warn("degenerate_triangles",
                  std::to_string(m.degenerate) + " zero-area triangles dropped from the LOD mesh");
  if (m.duplicate)
    reporter.warn("duplicate_triangles",
                  std::to_string(m.duplicate) + " duplicate triangles dropped from the LOD mesh");
  if (m.splitVertices || m.cutEdges)
    reporter.warn("non_manifold", std::to_string(m.cutEdges) +
                                      " edges with more than two faces (or wound both "
                                      "ways) cut open; " +
                                      std::to_string(m.splitVertices) + " vertices where " +
                                      "several fans meet split into one per fan (" +
                                      std::to_string(m.extraFans) +
                                      " added), each fan simplifying on its own");
}

// Where the LOD stops above its floor, what stops each edge that is left, both ways: as refused
// in the last pass, which collapsed nothing, so each refusal stands.
void reportFloorNotReached(const lod::CollapseMesh &mesh, lod::CollapseRules &rules,
                           const lod::Refusals &refusals, const LodOptions &o, Reporter &reporter) {
  auto reason = [&](uint32_t a, uint32_t b, const lod::EdgeFaces &edge) {
    const lod::Refusals::Slot slot = rules.slotOf(a, b, edge);
    lod::EdgeFaces faces;
    return refusals.stands(slot, a, b) ? refusals.why(slot) : rules.check(a, b, faces);
  };
  const size_t F = mesh.faces();
  size_t seam = 0, manifold = 0, normal = 0, edges = 0;
  for (uint32_t f = 0; f < F; ++f)
    for (uint32_t e = 0; mesh.alive[f] && e < 3; ++e) {
      const uint32_t a = mesh.fan.vertex[f][e], b = mesh.fan.vertex[f][(e + 1) % 3];
      const lod::EdgeFaces edge = mesh.edgeFaces(a, b);
      if (edge.sides == 2 && edge.face[0] != f)
        continue; // each edge once
      ++edges;
      using lod::Block;
      const Block ab = reason(a, b, edge), ba = reason(b, a, edge);
      seam += ab == Block::kSeam && ba == Block::kSeam;
      normal += (ab == Block::kNormal || ba == Block::kNormal) && ab != Block::kManifold &&
                ba != Block::kManifold;
      manifold += ab == Block::kManifold || ba == Block::kManifold;
    }
  auto pct = [](double x) { return std::to_string(int(std::lround(100 * x))) + "%"; };
  auto budget = [](double b) {
    char text[64];
    std::snprintf(text, sizeof text, "%g of 255", b);
    return std::string(text);
  };
  reporter.warn("lod_floor_not_reached",
                "the LOD stops at " + std::to_string(mesh.aliveFaces) + " of " + std::to_string(F) +
                    " triangles (" + pct(double(mesh.aliveFaces) / double(F)) + ", the floor is " +
                    pct(o.floorFraction) + "): no legal collapse is left. Of its " +
                    std::to_string(edges) + " edges, " + std::to_string(seam) +
                    " join two seam or boundary corners (UV seams, open borders, and hard "
                    "edges whose closing would change the colour by more than the seam budget, " +
                    budget(o.seamBudget) + ": each moves only along its line), " +
                    std::to_string(manifold) +
                    " would make the mesh non-manifold (a piece down to its last faces), " +
                    std::to_string(normal) + " would turn a face more than " +
                    std::to_string(int(o.maxNormalDeviationDeg)) + " degrees");
}

} // namespace

// The stages: the fan mesh (welded, repaired), its quadrics and special edges, the collapse
// loop, then the pack's order of vertices and triangles.
LodResult bakeLod(const std::vector<glm::vec3> &positions, const std::vector<uint32_t> &indices,
                  const LodOptions &o, Reporter &reporter, const std::vector<uint32_t> &group,
                  const std::vector<std::vector<glm::vec3>> &poses,
                  const LodAppearance *appearance) {
  checkInput(positions, indices, poses);
  LodResult r;
  r.inputTriangles = uint32_t(indices.size() / 3);
  lod::FanMesh fan = lod::buildFanMesh(positions, indices, group);
  reportRepairs(fan, reporter);
  if (fan.vertex.empty())
    throw Error("lod: the mesh has no triangle with an area");
  const std::vector<std::array<uint32_t, 3>> initialCorner = fan.render;
  lod::CollapseMesh mesh(std::move(fan), poses);
  if (appearance && o.seamBudget > 0)
    mesh.shading = lod::SeamShading(*appearance, mesh.fan.source, o.seamBudget);
  lod::CollapseRules rules(mesh, o.maxNormalDeviationDeg);
  lod::Refusals refusals(mesh.vertices(), mesh.faces());
  const size_t floorFaces = size_t(std::ceil(o.floorFraction * double(mesh.faces())));
  const lod::Removals removals = lod::collapseToFloor(mesh, rules, refusals, floorFaces);
  if (mesh.aliveFaces > floorFaces)
    reportFloorNotReached(mesh, rules, refusals, o, reporter);
  r.seamClosings = mesh.shading.closings();
  r.seamColourChange = mesh.shading.largestChange();
  size_t isolated = 0;
  const std::vector<uint32_t> newIndex =
      lod::numberVertices(mesh.fan, removals, indices, r, isolated);
  if (isolated)
    reporter.warn("isolated_vertices",
                  std::to_string(isolated) + " vertices no triangle uses: last in the LOD order");
  lod::orderTriangles(mesh.fan, initialCorner, removals, newIndex, r);
  return r;
}

} // namespace crowd
