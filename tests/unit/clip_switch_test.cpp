// Clip changes over time (clip_switch.h): scenes' "switch", the schedule every instance follows,
// and the preview's clip key crossfade.
#include <gtest/gtest.h>

#include "crowd/formats/error.h"
#include "crowd/runtime/clip_switch.h"
#include "crowd/runtime/preview_scene.h"

using namespace crowd;
using runtime::ClipSchedule;
using runtime::ClipState;
using runtime::parseScene;

namespace {

runtime::Scene switching(const std::string &clip, const std::string &sw, int count = 20) {
  return parseScene(R"({"packs": [{"path": "a"}], "instances": {"count": )" +
                        std::to_string(count) + R"(, "clip": )" + clip + R"(, "switch": )" + sw +
                        "}}",
                    "s.json");
}

std::string errorOf(const std::string &text) {
  try {
    parseScene(text, "s.json");
  } catch (const Error &e) {
    return e.what();
  }
  return "";
}

TEST(ClipSwitch, IntervalsFadesAndClipsFollowTheScene) {
  auto scene =
      switching(R"(["walk", "run", "idle"])", R"({"every": {"min": 3, "max": 8}, "fade": 0.5})");
  EXPECT_TRUE(scene.switching.enabled());
  ClipSchedule schedule(scene);
  ASSERT_TRUE(schedule.dynamic());
  size_t switches = 0;
  std::vector<size_t> played(3, 0);
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    ClipState last = schedule.at(i, 0.0);
    EXPECT_EQ(last.clip, scene.instances[i].clip);
    EXPECT_LT(last.from, 0);
    double lastSwitch = -1;
    for (double t = 0; t < 120; t += 0.05) {
      const ClipState s = schedule.at(i, t);
      if (s.fadeStart != last.fadeStart) { // a switch
        ++switches;
        EXPECT_NE(s.clip, last.clip); // always to another clip
        EXPECT_EQ(s.from, int32_t(last.clip));
        EXPECT_DOUBLE_EQ(s.fromOffset, last.offset); // the old clip plays on
        EXPECT_DOUBLE_EQ(s.fadeSeconds, 0.5);
        EXPECT_NEAR(t * scene.instances[i].speed + s.offset, t - s.fadeStart, 1e-9); // from 0
        if (lastSwitch >= 0) {
          EXPECT_GE(s.fadeStart - lastSwitch, 3 - 1e-9);
          EXPECT_LE(s.fadeStart - lastSwitch, 8 + 1e-9);
        }
        lastSwitch = s.fadeStart;
        EXPECT_FLOAT_EQ(s.weightAt(s.fadeStart), 0.0f);
        EXPECT_FLOAT_EQ(s.weightAt(s.fadeStart + 0.25), 0.5f);
        EXPECT_FLOAT_EQ(s.weightAt(s.fadeStart + 0.5), 1.0f);
      }
      ++played[s.clip];
      last = s;
    }
  }
  // 20 instances over 120 s, every 3 to 8 s: about 20 x 120 / 5.5 switches, every clip played.
  EXPECT_GT(switches, 300u);
  EXPECT_LT(switches, 1000u);
  for (size_t n : played)
    EXPECT_GT(n, 20u * 2400u / 6u);
}

TEST(ClipSwitch, AnyTimeGivesTheSameStateInAnyOrder) {
  auto scene = switching(R"(["walk", "run"])", R"({"every": 2, "fade": 0.3})", 5);
  ClipSchedule forward(scene), jumping(scene);
  for (double t : {50.0, 3.0, 0.1, 17.7, 17.8, 2.0}) {
    ClipSchedule fresh(scene);
    for (size_t i = 0; i < scene.instances.size(); ++i) {
      const ClipState a = jumping.at(i, t), b = fresh.at(i, t);
      EXPECT_EQ(a.clip, b.clip);
      EXPECT_EQ(a.fadeStart, b.fadeStart);
      EXPECT_EQ(a.offset, b.offset);
    }
  }
  // Two clips alternate: every switch goes to the other one, every 2 s.
  size_t switches = 0;
  for (double t = 0; t < 20; t += 0.1) {
    const ClipState s = forward.at(0, t);
    if (s.from >= 0) {
      EXPECT_EQ(s.clip, 1u - uint32_t(s.from));
      switches += s.fadeStart > t - 0.1;
    }
  }
  EXPECT_GE(switches, 9u);
  EXPECT_LE(switches, 10u);
}

TEST(ClipSwitch, OneClipOrNoSwitchIsStatic) {
  auto one = switching(R"("walk")", R"({"every": 2})", 3);
  ClipSchedule s(one);
  for (double t = 0; t < 30; t += 0.5)
    EXPECT_LT(s.at(1, t).from, 0); // nowhere to switch to: no fade ever
  auto none = parseScene(R"({"packs": [{"path": "a"}], "instances": {"count": 3}})", "s.json");
  EXPECT_FALSE(none.switching.enabled());
  EXPECT_FALSE(ClipSchedule(none).dynamic());
}

TEST(ClipSwitch, BadSwitchesAreClearErrors) {
  const std::string head = R"({"packs": [{"path": "a"}], "instances": {"clip": ["a", "b"], )";
  EXPECT_NE(errorOf(head + R"("switch": {"fade": 0.3}}})").find("/instances/switch:"),
            std::string::npos);
  EXPECT_NE(errorOf(head + R"("switch": {"every": {"min": 3, "max": 2}}}})").find("outside"),
            std::string::npos);
  EXPECT_NE(errorOf(head + R"("switch": {"every": 1, "fade": 2}}})").find("/instances/switch/fade"),
            std::string::npos); // a fade longer than the shortest interval
  EXPECT_NE(errorOf(head + R"("switch": {"every": 1, "blend": 2}}})").find("unknown key 'blend'"),
            std::string::npos);
}

TEST(ClipSwitch, ThePreviewClipKeyCrossfadesBetweenSingleClips) {
  runtime::Scene next;
  next.instances.resize(3);
  runtime::crossfadeFrom(next, {0, 1}, {1, 1}, 12.5);
  for (const auto &inst : next.instances) {
    EXPECT_EQ(inst.fade.from, 0);
    EXPECT_EQ(inst.fade.start, 12.5);
    EXPECT_EQ(inst.fade.seconds, runtime::kClipKeyFadeSeconds);
  }
  ClipSchedule s(next);
  EXPECT_TRUE(s.dynamic());
  EXPECT_FLOAT_EQ(s.at(0, 12.5 + runtime::kClipKeyFadeSeconds / 2).weightAt(12.65), 0.5f);
  runtime::Scene all;
  all.instances.resize(3);
  runtime::crossfadeFrom(all, {-1, -1}, {0, -1}, 1.0); // from every clip: a new row, no fade
  runtime::crossfadeFrom(all, {0, -1}, {1, 0}, 1.0);   // another outfit too: a new row
  for (const auto &inst : all.instances)
    EXPECT_LT(inst.fade.from, 0);
}

} // namespace
