// A scene's world: its keys and their errors, and the instances its agents move (where they
// stand, the clip their pace plays, the crossfade when it changes, the same on every replay).
#include <gtest/gtest.h>

#include "crowd/formats/error.h"
#include "crowd/runtime/scene.h"
#include "crowd/runtime/world.h"
#include "flat_terrain.h"

using namespace crowd;
using namespace crowd::runtime;

namespace {

const char *kWorldScene = R"({"packs": [{"path": "h.crowdpack"}],
  "world": {"terrain": "../out/v.crowdpack", "behaviour": "b.png",
            "callbacks": {"image": "c.png", "bus_stops": [{"colour": [0, 0, 255], "every": 15}]},
            "attractors": [[1, 2]],
            "spawn": [{"min": [0, 0], "max": [5, 5], "count": 30},
                      {"min": [5, 0], "max": [10, 5], "count": 10}],
            "clips": {"idle": "stand", "walk": "walk", "run": "run"}},
  "instances": {}})";

std::string errorOf(const std::string &text) {
  try {
    parseScene(text, "s.json");
  } catch (const Error &e) {
    return e.what();
  }
  return "no error";
}

// A flat walkable 10 x 10 m terrain.
pack::Terrain flat() { return test::flatTerrain(40, 40); }

} // namespace

TEST(World, SceneKeysAndTheirErrors) {
  const Scene s = parseScene(kWorldScene, "scenes/s.json");
  ASSERT_TRUE(s.world.enabled());
  EXPECT_EQ(s.world.terrainPath, "out/v.crowdpack");
  EXPECT_EQ(s.world.behaviourPath, "scenes/b.png");
  EXPECT_EQ(s.world.callbackPath, "scenes/c.png");
  ASSERT_EQ(s.world.busStops.size(), 1u);
  EXPECT_EQ(s.world.busStops[0].every, 15);
  EXPECT_EQ(s.instances.size(), 40u) << "one instance per agent";
  EXPECT_EQ(s.clipNames, (std::vector<std::string>{"stand", "walk", "run"}));
  EXPECT_EQ(parseScene(kWorldScene, "s.json", 80).instances.size(), 80u) << "--instances";

  std::string bad = kWorldScene;
  EXPECT_NE(errorOf(std::string(bad).replace(bad.find("\"instances\": {}"), 15,
                                             "\"instances\": {\"count\": 3}"))
                .find("the agents give the count"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(bad).replace(bad.find("[0, 0, 255]"), 11, "[0, 0, 256]"))
                .find("whole numbers 0 to 255"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"packs": [{"path": "h"}], "world": {"spawn": []}, "instances": {}})")
                .find("\"terrain\""),
            std::string::npos);
}

TEST(World, InstancesStandWhereTheirAgentsStandAndPlayTheirPace) {
  Scene s = parseScene(R"({"packs": [{"path": "h.crowdpack"}],
    "world": {"terrain": "v.crowdpack", "spawn": [{"min": [1, 1], "max": [9, 9], "count": 20}],
              "runners": 0.5, "fade": 0.25},
    "instances": {}})",
                       "s.json");
  // A red (wait) band across the middle: walkers crossing it stand there a while.
  RgbaImage waits{40, 40, std::vector<uint8_t>(40 * 40 * 4, 0)};
  for (uint32_t z = 18; z < 22; ++z)
    for (uint32_t x = 0; x < 40; ++x)
      waits.rgba[4 * (z * 40 + x)] = waits.rgba[4 * (z * 40 + x) + 3] = 255;
  SceneWorld world(s, flat(), waits, {});
  bool faded = false, stood = false, ran = false;
  for (int k = 1; k <= 300; ++k) {
    world.advanceTo(k / 30.0);
    for (size_t i = 0; i < world.motions().size(); ++i) {
      const InstanceMotion &m = world.motions()[i];
      const Agent &a = world.crowd().agents()[i];
      ASSERT_EQ(m.position, glm::vec3(a.position.x, a.height, a.position.y));
      ASSERT_EQ(m.yaw, a.heading);
      stood |= m.clip.clip == 0;
      ran |= m.clip.clip == 2;
      if (m.clip.from >= 0) { // a fade from the last pace, started when the pace changed
        faded = true;
        ASSERT_NE(uint32_t(m.clip.from), m.clip.clip);
        ASSERT_EQ(m.clip.fadeSeconds, 0.25);
        ASSERT_LE(m.clip.fadeStart, k / 30.0 + 1e-9);
      }
      if (m.clip.clip != 0) { // walk and run at the agent's own pace
        ASSERT_GT(m.speed, 0.8f);
      }
    }
  }
  EXPECT_TRUE(stood && ran && faded);
  // Going back in time replays the same crowd.
  const auto later = world.motions();
  world.advanceTo(2);
  world.advanceTo(10);
  for (size_t i = 0; i < later.size(); ++i)
    EXPECT_EQ(world.motions()[i].position, later[i].position);
  // Images of another size than the terrain's grid are refused.
  EXPECT_THROW(SceneWorld(s, flat(), RgbaImage{20, 40, std::vector<uint8_t>(20 * 40 * 4)}, {}),
               Error);
}
