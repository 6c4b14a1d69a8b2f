// The terrain bake on environments whose maps are known: a box on flat ground (heights, a roof
// nobody reaches, a shadow of known length), steps and ramps (the walkable rule), the sample
// village, and the failure modes (nothing walkable, NaN, absurd extents, damaged chunks).
#include <cmath>

#include <gtest/gtest.h>

#include "crowd/bake/import.h"
#include "crowd/bake/terrain_bake.h"
#include "crowd/formats/error.h"
#include "crowd/formats/terrain.h"
#include "crowd/samples/samples.h"
#include "gltf_writer.h"

using namespace crowd;

namespace {

// An unskinned environment of boxes (lo, hi) and ramps, every vertex on one root node.
struct Scene {
  Character c;
  Scene() {
    c.nodes = {Node{"root"}};
    c.nodeOrder = {0};
    c.jointNodes = {0};
    c.inverseBind = {glm::dmat4(1.0)};
    c.skinned = false;
    c.mesh.parts.push_back({"all", 0, 0});
  }
  void quad(glm::vec3 a, glm::vec3 b, glm::vec3 cc, glm::vec3 d) {
    const uint32_t first = uint32_t(c.mesh.positions.size());
    const glm::vec3 n = glm::normalize(glm::cross(b - a, d - a));
    for (const auto &p : {a, b, cc, d}) {
      c.mesh.positions.push_back(p);
      c.mesh.normals.push_back(n);
      c.mesh.joints.push_back({0, 0, 0, 0});
      c.mesh.weights.push_back({1, 0, 0, 0});
    }
    for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u})
      c.mesh.indices.push_back(first + i);
    c.mesh.parts[0].indexCount = uint32_t(c.mesh.indices.size());
  }
  void ground(float half, float y = 0) {
    quad({-half, y, -half}, {-half, y, half}, {half, y, half}, {half, y, -half});
  }
  void box(glm::vec3 lo, glm::vec3 hi) { // top and the four sides
    quad({lo.x, hi.y, lo.z}, {lo.x, hi.y, hi.z}, {hi.x, hi.y, hi.z}, {hi.x, hi.y, lo.z});
    quad({lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z});
    quad({hi.x, lo.y, lo.z}, {lo.x, lo.y, lo.z}, {lo.x, hi.y, lo.z}, {hi.x, hi.y, lo.z});
    quad({hi.x, lo.y, hi.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {hi.x, hi.y, hi.z});
    quad({lo.x, lo.y, lo.z}, {lo.x, lo.y, hi.z}, {lo.x, hi.y, hi.z}, {lo.x, hi.y, lo.z});
  }
};

// The cell holding world point (x, z).
size_t cellAt(const pack::Terrain &t, double x, double z) {
  return t.cellIndex(uint32_t((x - t.originX) / t.cell), uint32_t((z - t.originZ) / t.cell));
}

pack::Ground groundAt(const pack::Terrain &t, double x, double z) {
  return pack::Ground(t.ground[cellAt(t, x, z)]);
}

TerrainBakeResult bake(const Scene &s, TerrainOptions o = {}) {
  Reporter r;
  return bakeTerrain(s.c, o, r);
}

} // namespace

TEST(Terrain, ABoxOnFlatGroundIsARoofNobodyReachesAndCastsItsShadow) {
  Scene s;
  s.ground(10);
  s.box({-1, 0, -1}, {1, 4, 1});
  TerrainOptions o;
  o.light = {1, 1, 0}; // 45 degrees up, towards +x: the shadow falls towards -x
  Reporter reporter;
  const TerrainBakeResult r = bakeTerrain(s.c, o, reporter);
  const pack::Terrain &t = r.terrain;
  EXPECT_EQ(t.width, 80u);
  EXPECT_EQ(t.depth, 80u);
  EXPECT_FLOAT_EQ(t.heights[cellAt(t, 0.1, 0.1)], 4.0f);
  EXPECT_FLOAT_EQ(t.heights[cellAt(t, 5, 5)], 0.0f);
  EXPECT_EQ(groundAt(t, 0.1, 0.1), pack::Ground::Blocked);
  EXPECT_EQ(groundAt(t, 5, 5), pack::Ground::Walkable);
  EXPECT_EQ(r.empty, 0u);
  EXPECT_EQ(r.unreachable, 64u); // the 2 x 2 m roof at 0.25 m cells
  ASSERT_EQ(reporter.warnings().size(), 1u);
  EXPECT_EQ(reporter.warnings()[0].code, "terrain_unreachable");
  // 2 m from the box's shadowed face the ray towards the light passes it 2 m up: a point of the
  // cell below 4 - 2 = 2 m is in shadow (within a cell: the march samples whole cells).
  EXPECT_NEAR(t.shadowHeights[cellAt(t, -3.1, 0.1)], 2.0, 0.26);
  EXPECT_NEAR(t.shadowHeights[cellAt(t, -1.6, 0.1)], 3.5, 0.26);
  EXPECT_FLOAT_EQ(t.shadowHeights[cellAt(t, -5.6, 0.1)], 0.0f); // past the shadow's 4 m
  EXPECT_FLOAT_EQ(t.shadowHeights[cellAt(t, 3.1, 0.1)], 0.0f);  // on the lit side
  EXPECT_FLOAT_EQ(t.shadowHeights[cellAt(t, -3.1, 2.1)], 0.0f); // beside the shadow
  // The shadow on the ground is the box's 2 x 4 m footprint cast 4 m: 128 cells, give or take
  // its edges.
  EXPECT_NEAR(double(r.walkableInShadow), 128, 16);
  // The mesh comes along in world space, with its colours.
  EXPECT_EQ(t.indices.size(), s.c.mesh.indices.size());
  EXPECT_EQ(t.colours.size(), 4 * s.c.mesh.positions.size());
}

TEST(Terrain, StepsLeadUpAndRampsSteeperThanTheLimitBlock) {
  Scene s;
  s.ground(10);
  // A platform 0.45 m up at z > 4, with 0.15 m steps up to it from z = 2; one 1 m up at x < -6.
  s.box({-10, 0, 4}, {10, 0.45f, 10});
  s.box({-2, 0, 2}, {2, 0.15f, 3});
  s.box({-2, 0, 3}, {2, 0.30f, 4});
  s.box({-10, 0, -10}, {-6, 1.0f, -4});
  // Ramps from the ground along +x: 20 degrees (walkable) and 50 degrees (too steep).
  const float rise20 = std::tan(glm::radians(20.0f)) * 3,
              rise50 = std::tan(glm::radians(50.0f)) * 3;
  s.quad({2, 0, -3}, {2, 0, -1}, {5, rise20, -1}, {5, rise20, -3});
  s.quad({2, 0, -8}, {2, 0, -6}, {5, rise50, -6}, {5, rise50, -8});
  const pack::Terrain t = bake(s).terrain;
  EXPECT_EQ(groundAt(t, 0.1, 7), pack::Ground::Walkable) << "the steps lead up";
  EXPECT_FLOAT_EQ(t.heights[cellAt(t, 0.1, 7)], 0.45f);
  EXPECT_EQ(groundAt(t, -8, -7), pack::Ground::Blocked) << "a 1 m platform is out of reach";
  EXPECT_EQ(groundAt(t, 3.5, -2), pack::Ground::Walkable);
  EXPECT_EQ(groundAt(t, 3.5, -7), pack::Ground::Blocked);
  TerrainOptions steeper;
  steeper.maxSlopeDeg = 55;
  EXPECT_EQ(groundAt(bake(s, steeper).terrain, 3.5, -7), pack::Ground::Walkable);
}

TEST(Terrain, TheSampleVillageBakesTheSameOnAnyThreadCountAndRoundTrips) {
  const std::string dir = test::tempDir("terrain_village");
  samples::writeSamples(dir);
  Reporter reporter;
  const Character village = importGltf(dir + "/" + samples::kVillageFile, {}, reporter);
  TerrainOptions one, two;
  one.threads = 1, two.threads = 2;
  Reporter r1, r2;
  const TerrainBakeResult a = bakeTerrain(village, one, r1), b = bakeTerrain(village, two, r2);
  const auto bytes = pack::encode(a.terrain);
  EXPECT_EQ(bytes, pack::encode(b.terrain));
  const pack::Terrain &t = a.terrain;
  EXPECT_EQ(a.empty, 0u) << "no crack between the ground's triangles";
  EXPECT_EQ(groundAt(t, 0, -30), pack::Ground::Walkable) << "the terrace, up its steps";
  EXPECT_NEAR(t.heights[cellAt(t, 0, -30)], 0.45, 1e-5);
  EXPECT_EQ(groundAt(t, 4.5, 4.5), pack::Ground::Blocked) << "the planter";
  EXPECT_EQ(groundAt(t, -20, -16), pack::Ground::Blocked) << "a roof";
  EXPECT_EQ(groundAt(t, 30, 0), pack::Ground::Walkable) << "the slope to the east";
  // Measured: 94,056 walkable cells, 4,959 of them in shadow; 8,344 blocked, every one of them
  // unreachable (roofs and the planter's top): each held within 2x.
  EXPECT_GE(a.walkable, 47028u);
  EXPECT_LE(a.walkable, 102400u - a.blocked);
  EXPECT_GE(a.walkableInShadow, 2480u);
  EXPECT_LE(a.walkableInShadow, 9918u);
  EXPECT_GE(a.blocked, 4172u);
  EXPECT_LE(a.blocked, 16688u);
  EXPECT_EQ(a.unreachable, a.blocked);
  const pack::Terrain back = pack::decodeTerrain(bytes, "village");
  EXPECT_EQ(pack::encode(back), bytes);
}

TEST(Terrain, FailureModesAreClearErrors) {
  auto message = [](const Scene &s, TerrainOptions o = {}) {
    try {
      bake(s, o);
    } catch (const Error &e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  Scene steep; // only a 60 degree ramp: nowhere to stand
  steep.quad({0, 0, 0}, {0, 0, 2}, {2, 3.5f, 2}, {2, 3.5f, 0});
  EXPECT_NE(message(steep).find("no walkable cell"), std::string::npos) << message(steep);
  Scene nan;
  nan.ground(5);
  nan.c.mesh.positions[1].y = NAN;
  EXPECT_NE(message(nan).find("vertex 1 is not finite"), std::string::npos) << message(nan);
  Scene huge;
  huge.ground(1e9f);
  EXPECT_NE(message(huge).find("(raise --cell)"), std::string::npos) << message(huge);
  Scene flat;
  flat.ground(5);
  TerrainOptions below;
  below.light = {1, -1, 0};
  EXPECT_NE(message(flat, below).find("above the horizon"), std::string::npos);
  EXPECT_EQ(message(Scene()), "environment: no triangles to stand on");

  // Damaged chunks: cut short, an unknown ground code, a shadow below its surface.
  const pack::Terrain t = bake(flat).terrain;
  std::vector<uint8_t> bytes = pack::encode(t);
  auto decodeError = [](std::vector<uint8_t> b) {
    try {
      pack::decodeTerrain(b, "TERR");
    } catch (const Error &e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(decodeError({bytes.begin(), bytes.begin() + 200}).find("TERR"), std::string::npos);
  pack::Terrain bad = t;
  bad.ground[3] = 9;
  EXPECT_NE(decodeError(pack::encode(bad)).find("unknown code"), std::string::npos);
  bad = t;
  bad.shadowHeights[5] = bad.heights[5] - 1;
  EXPECT_NE(decodeError(pack::encode(bad)).find("below its surface"), std::string::npos);
  bad = t;
  bad.indices[0] = 1000000;
  EXPECT_NE(decodeError(pack::encode(bad)).find("past the"), std::string::npos);
}
