// The LOD bake's stages on a quad whose diagonal is a UV seam (two triangles sharing the
// diagonal's positions through different render vertices): the collapse mesh marks its four
// border edges open and the diagonal a seam, each in one face; the rules let a corner slide
// along its border, keep a seam vertex on its line and refuse what is no longer an edge.
#include <gtest/gtest.h>

#include <bit>
#include <vector>

#include "../../bake/src/lod/collapse_mesh.h"
#include "../../bake/src/lod/collapse_rules.h"

namespace {

using namespace crowd::lod;

FanMesh seamQuad() {
  // 0 1 2 3: the quad's corners; 4 and 5 sit at 0 and 2 for the second triangle (its own UVs).
  const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0},
                                    {0, 1, 0}, {0, 0, 0}, {1, 1, 0}};
  return buildFanMesh(p, {0, 1, 2, 4, 5, 3}, {});
}

TEST(CollapseStages, BordersAreOpenAndTheSeamSpecialEachInOneFace) {
  const CollapseMesh mesh(seamQuad(), {});
  ASSERT_EQ(mesh.faces(), 2u);
  ASSERT_EQ(mesh.vertices(), 4u); // the seam's copies weld by position
  int open = 0, special = 0;
  for (size_t f = 0; f < mesh.faces(); ++f)
    open += std::popcount(unsigned(mesh.open[f])),
        special += std::popcount(unsigned(mesh.special[f]));
  EXPECT_EQ(open, 4);
  EXPECT_EQ(special, 5);
  const uint32_t a = mesh.fan.vertex[0][0], c = mesh.fan.vertex[0][2]; // the diagonal's ends
  EXPECT_EQ(mesh.edgeFaces(a, c).sides, 2u);
  EXPECT_EQ(mesh.edgeFaces(a, mesh.fan.vertex[0][1]).sides, 1u);
}

TEST(CollapseStages, ACornerSlidesAlongItsBorderButNotOffItsSeam) {
  const CollapseMesh mesh(seamQuad(), {});
  CollapseRules rules(mesh, 75);
  const auto &f = mesh.fan.vertex;
  const uint32_t v0 = f[0][0], v1 = f[0][1], v2 = f[0][2];
  const uint32_t v3 = f[1][2] != v0 && f[1][2] != v2 ? f[1][2] : f[1][1];
  EdgeFaces edge;
  EXPECT_EQ(rules.check(v1, v0, edge), Block::kNone); // along its two border edges
  EXPECT_EQ(edge.sides, 1u);
  EXPECT_EQ(rules.check(v2, v0, edge), Block::kSeam); // three special edges meet at v2
  EXPECT_EQ(rules.check(v1, v3, edge), Block::kNoEdge);
  // A refusal's slot: the face that winds the edge, or the reverse of an open one.
  EdgeFaces border = mesh.edgeFaces(v0, v1);
  EXPECT_FALSE(rules.slotOf(v0, v1, border).reverse);
  EXPECT_TRUE(rules.slotOf(v1, v0, border).reverse);
}

} // namespace
