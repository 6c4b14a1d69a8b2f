// The agents' four layers on hand-made terrains: they never stand where they may not, never
// share a cell, turn before they reach a wall, wait, gather, and are the same on every run;
// spawning and the images fail clearly.
#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "crowd/formats/error.h"
#include "crowd/runtime/agents.h"
#include "flat_terrain.h"
#include "fresh_process.h"

using namespace crowd;
using namespace crowd::runtime;

namespace {

pack::Terrain flat(uint32_t width, uint32_t depth) { return test::flatTerrain(width, depth); }

// Cells [x0, x1) x [z0, z1) set to `ground` at `height`.
void block(pack::Terrain &t, uint32_t x0, uint32_t z0, uint32_t x1, uint32_t z1,
           pack::Ground ground, float height = 0) {
  for (uint32_t z = z0; z < z1; ++z)
    for (uint32_t x = x0; x < x1; ++x) {
      t.ground[t.cellIndex(x, z)] = uint8_t(ground);
      t.heights[t.cellIndex(x, z)] = t.shadowHeights[t.cellIndex(x, z)] = height;
    }
}

size_t cellOf(const pack::Terrain &t, glm::vec2 p) {
  return t.cellIndex(uint32_t(p.x / t.cell), uint32_t(p.y / t.cell));
}

std::vector<uint8_t> image(const pack::Terrain &t, std::array<uint8_t, 4> fill) {
  std::vector<uint8_t> rgba;
  for (size_t i = 0; i < t.cells(); ++i)
    rgba.insert(rgba.end(), fill.begin(), fill.end());
  return rgba;
}

} // namespace

TEST(Agents, NeverWhereTheyMayNotStandNorTwoInACell) {
  pack::Terrain t = flat(160, 160);                          // 40 x 40 m
  block(t, 40, 40, 80, 80, pack::Ground::Blocked, 6);        // a building
  block(t, 100, 20, 120, 140, pack::Ground::Walkable, 0.5f); // a 0.5 m platform, no steps
  Crowd crowd(t, {});
  crowd.spawn({{{0, 0}, {40, 40}, 2000}});
  EXPECT_GT(crowd.figures().spawnedMoved, 0u) << "some landed in the building or the platform";
  std::vector<float> heights, spawned;
  for (const auto &a : crowd.agents())
    heights.push_back(a.height);
  spawned = heights;
  for (int s = 0; s < 600; ++s) {
    crowd.step();
    std::set<std::pair<int, int>> cells;
    for (size_t i = 0; i < crowd.agents().size(); ++i) {
      const Agent &a = crowd.agents()[i];
      ASSERT_TRUE(a.position.x >= 0 && a.position.y >= 0 && a.position.x < 40 && a.position.y < 40);
      ASSERT_EQ(t.ground[cellOf(t, a.position)], uint8_t(pack::Ground::Walkable));
      ASSERT_LE(std::abs(a.height - heights[i]), t.stepHeight) << "agent " << i << " step " << s;
      heights[i] = a.height;
      ASSERT_TRUE(cells.insert({int(a.position.x / 0.5f), int(a.position.y / 0.5f)}).second)
          << "two agents in one cell at step " << s;
    }
  }
  // Nobody climbs onto the 0.5 m platform or steps off it.
  for (size_t i = 0; i < crowd.agents().size(); ++i)
    EXPECT_EQ(crowd.agents()[i].height, spawned[i]);
  EXPECT_GT(crowd.figures().blockedAgentSteps, 0u); // 2000 agents in 40 x 40 m do meet
}

TEST(Agents, LookingAheadTheyTurnBeforeTheWall) {
  pack::Terrain t = flat(320, 80);                    // 80 x 20 m
  block(t, 0, 60, 320, 80, pack::Ground::Blocked, 3); // a wall across z = 15 m
  auto blockedSteps = [&](uint32_t lookAhead) {
    AgentSettings s;
    s.lookAhead = lookAhead;
    s.runners = 0;
    Crowd crowd(t, s);
    crowd.spawn({{{40, 2}, {40.01f, 2.01f}, 1}});
    // Walk straight at the wall: heading 0 is +z. Steer it there by an attractor far beyond.
    crowd.addAttractor({40, 100});
    std::vector<uint8_t> blue = image(t, {0, 0, 255, 255});
    crowd.setBehaviours(t.width, t.depth, blue);
    for (int k = 0; k < 600; ++k)
      crowd.step();
    EXPECT_GT(crowd.agents()[0].position.y, 12) << "it reached the wall";
    return crowd.figures().blockedAgentSteps;
  };
  // Pulled at the wall for 20 s, it reaches it and slides along it (not yet to the map's end);
  // it never stops against it when it looks 1.5 m ahead, and does when it looks 0.5 m ahead.
  EXPECT_EQ(blockedSteps(3), 0u);
  EXPECT_GT(blockedSteps(1), 0u);
}

TEST(Agents, TheSameCrowdInAFreshProcessAndAnotherWithAnotherSeed) {
  pack::Terrain t = flat(120, 120);
  block(t, 50, 50, 70, 70, pack::Ground::Blocked, 4);
  auto run = [&](uint64_t seed) {
    AgentSettings s;
    s.seed = seed;
    Crowd crowd(t, s);
    crowd.setBehaviours(t.width, t.depth, image(t, {0, 255, 0, 255})); // wander everywhere
    crowd.spawn({{{0, 0}, {30, 30}, 800}});
    for (int k = 0; k < 200; ++k)
      crowd.step();
    std::vector<float> out;
    for (const auto &a : crowd.agents())
      out.insert(out.end(), {a.position.x, a.position.y, a.heading});
    return out;
  };
  const auto seven = test::sameInAFreshProcess([&] { return test::bytesOf(run(7)); });
  if (!seven)
    return;
  EXPECT_NE(*seven, test::bytesOf(run(8)));
}

TEST(Agents, WaitCellsAndABusStopHoldThenRelease) {
  pack::Terrain t = flat(80, 80);
  std::vector<uint8_t> colours = image(t, {255, 255, 255, 255});
  std::vector<uint8_t> stops = image(t, {0, 0, 0, 0});
  for (uint32_t z = 0; z < 80; ++z)
    for (uint32_t x = 0; x < 80; ++x) {
      uint8_t *c = &colours[4 * t.cellIndex(x, z)], *s = &stops[4 * t.cellIndex(x, z)];
      if (z >= 20 && z < 24) // a red band: wait
        c[1] = c[2] = 0;
      if (z >= 40 && z < 44) // a bus stop band
        s[0] = 200, s[1] = 10, s[2] = 10, s[3] = 255;
    }
  AgentSettings settings;
  settings.runners = 0;
  settings.waitSeconds = 2;
  Crowd crowd(t, settings);
  crowd.setBehaviours(t.width, t.depth, colours);
  crowd.setCallbacks(t.width, t.depth, stops, {{"bus_stop", {200, 10, 10}, holdUntilEvery(10)}});
  crowd.addAttractor({10, 100});
  crowd.spawn({{{10, 1}, {10.01f, 1.01f}, 1}});
  std::vector<uint8_t> attract = colours; // blue where white, so that it walks north
  for (size_t i = 0; i < t.cells(); ++i)
    if (attract[4 * i] == 255 && attract[4 * i + 1] == 255)
      attract[4 * i] = attract[4 * i + 1] = 0;
  crowd.setBehaviours(t.width, t.depth, attract);
  double waitedAt = -1, stoppedAt = -1, releasedAt = -1;
  for (int k = 0; k < 13 * 30; ++k) { // 13 s: past the release, before the map's end
    crowd.step();
    const Agent &a = crowd.agents()[0];
    const float z = a.position.y;
    if (a.speed == 0 && z >= 5 && z < 6 && waitedAt < 0)
      waitedAt = crowd.time();
    if (a.speed == 0 && z >= 10 && z < 11 && stoppedAt < 0)
      stoppedAt = crowd.time();
    if (stoppedAt >= 0 && releasedAt < 0 && a.speed > 0)
      releasedAt = crowd.time();
  }
  ASSERT_GE(waitedAt, 0) << "it never waited in the red band";
  ASSERT_GE(stoppedAt, 0) << "the bus stop never held it";
  EXPECT_NEAR(releasedAt, std::ceil(stoppedAt / 10) * 10, 0.1) << "released on the timer";
  EXPECT_EQ(crowd.figures().blockedAgentSteps, 0u);
}

TEST(Agents, FailureModesAreClearErrors) {
  pack::Terrain t = flat(40, 40); // 10 x 10 m: 400 cells of 0.5 m
  Crowd crowd(t, {});
  auto message = [](const std::function<void()> &f) {
    try {
      f();
    } catch (const Error &e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message([&] {
              crowd.setBehaviours(20, 40, std::vector<uint8_t>(20 * 40 * 4));
            }).find("is 20x40 pixels; the terrain's grid is 40x40"),
            std::string::npos);
  EXPECT_NE(message([&] {
              crowd.spawn({{{0, 0}, {10, 10}, 401}});
            }).find("holds at most 400"),
            std::string::npos);
  EXPECT_NE(message([&] {
              crowd.spawn({{{0, 0}, {10, 10}, 1000001}});
            }).find("at most 1000000"),
            std::string::npos);
  AgentSettings bad;
  bad.step = 0;
  EXPECT_NE(message([&] { Crowd c(t, bad); }).find("'step'"), std::string::npos);
  // Spawned far outside the map: clamped to its edge, then inside it.
  crowd.spawn({{{-50, -50}, {-40, -40}, 3}});
  for (const auto &a : crowd.agents())
    EXPECT_TRUE(a.position.x >= 0 && a.position.y >= 0 && a.position.x < 10 && a.position.y < 10);
}
