#include <filesystem>
#include <set>
#include <unistd.h>

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include "crowd/formats/error.h"
#include "crowd/runtime/scene.h"
#include "fresh_process.h"

using namespace crowd;
using runtime::parseScene;

namespace {

std::string errorOf(const std::string &text) {
  try {
    parseScene(text, "s.json");
  } catch (const Error &e) {
    return e.what();
  }
  return "";
}

const char *kMinimal = R"({"packs": [{"path": "a.crowdpack"}], "instances": {"count": 5}})";

TEST(Scene, DefaultsAndPathsRelativeToTheScene) {
  auto s = parseScene(kMinimal, "scenes/s.json");
  EXPECT_EQ(s.packPaths, std::vector<std::string>{"scenes/a.crowdpack"});
  EXPECT_EQ(s.packNames, std::vector<std::string>{"a"});
  ASSERT_EQ(s.instances.size(), 5u);
  EXPECT_EQ(s.clipNames, std::vector<std::string>{""});     // the pack's first clip
  EXPECT_EQ(s.impostorPaths, std::vector<std::string>{""}); // no impostors
  auto h =
      parseScene(R"({"packs": [{"path": "a", "impostor": "../b.crowdpack"}], "instances": {}})",
                 "scenes/s.json");
  EXPECT_EQ(h.impostorPaths, std::vector<std::string>{"b.crowdpack"});
  EXPECT_NE(
      errorOf(R"({"packs": [{"path": "a", "impostor": 3}], "instances": {}})").find("s.json:1:"),
      std::string::npos);
}

TEST(Scene, TriangleBudget) {
  EXPECT_EQ(parseScene(kMinimal, "s.json").budget, 0u); // none: full detail
  EXPECT_EQ(
      parseScene(R"({"packs": [{"path": "a"}], "instances": {}, "budget": 2000000})", "s.json")
          .budget,
      2000000u);
  EXPECT_NE(errorOf(R"({"packs": [{"path": "a"}], "instances": {},
                        "budget": -5})")
                .find("s.json:2:"),
            std::string::npos);
  EXPECT_NE(
      errorOf(R"({"packs": [{"path": "a"}], "instances": {}, "budget": "lots"})").find("budget"),
      std::string::npos);
}

TEST(Scene, PaletteSlot) {
  EXPECT_EQ(parseScene(kMinimal, "s.json").paletteSlot, runtime::kClipSampleSlot);
  const auto slot = [](const std::string &v) {
    return parseScene(R"({"packs": [{"path": "a"}], "instances": {}, "palette_slot": )" + v + "}",
                      "s.json")
        .paletteSlot;
  };
  EXPECT_EQ(slot("\"clip\""), runtime::kClipSampleSlot);
  EXPECT_EQ(slot("0"), 0.0f);
  EXPECT_EQ(slot("0.05"), 0.05f);
  for (const char *bad : {"-1", "11", "\"frame\"", "[1]"})
    EXPECT_NE(
        errorOf(std::string(R"({"packs": [{"path": "a"}], "instances": {}, "palette_slot": )") +
                bad + "}")
            .find("palette_slot"),
        std::string::npos)
        << bad;
}

TEST(Scene, GridRandomAndListPlacements) {
  auto grid = parseScene(R"({"packs": [{"path": "a"}], "instances": {"count": 9,
      "placement": {"type": "grid", "spacing": 2}}})",
                         "s.json");
  EXPECT_DOUBLE_EQ(grid.instances[0].position.x, -2);
  EXPECT_DOUBLE_EQ(grid.instances[8].position.z, 2);
  auto random = parseScene(R"({"packs": [{"path": "a"}], "instances": {"count": 50, "seed": 4,
      "placement": {"type": "random", "min": [-1, 0, -2], "max": [1, 0, 2]}}})",
                           "s.json");
  for (const auto &i : random.instances) {
    EXPECT_LE(std::abs(i.position.x), 1);
    EXPECT_LE(std::abs(i.position.z), 2);
  }
  const auto parent = test::sameInAFreshProcess([] { // seeded: the same in any process
    auto seeded = parseScene(R"({"packs": [{"path": "a"}], "instances": {"count": 50, "seed": 4,
      "placement": {"type": "random", "min": [-1, 0, -2], "max": [1, 0, 2]}}})",
                             "s.json");
    std::vector<double> xyz;
    for (const auto &i : seeded.instances)
      xyz.insert(xyz.end(), {i.position.x, i.position.y, i.position.z, i.yaw});
    return test::bytesOf(xyz);
  });
  if (!parent)
    return;
  auto list = parseScene(R"({"packs": [{"path": "a"}], "instances": {
      "placement": {"type": "list", "positions": [[1, 2], [3, 4, 90]]}}})",
                         "s.json");
  ASSERT_EQ(list.instances.size(), 2u);
  EXPECT_NEAR(list.instances[1].yaw, 1.5707963, 1e-6);
  auto more = parseScene(R"({"packs": [{"path": "a"}], "instances": {
      "placement": {"type": "list", "positions": [[1, 2], [3, 4, 90]]}}})",
                         "s.json", 5);
  EXPECT_EQ(more.instances.size(), 5u) << "--instances overrides, the list repeats";
}

TEST(Scene, DistributionsStayInRange) {
  auto s = parseScene(R"({"packs": [{"path": "a"}], "instances": {"count": 100,
      "clip": ["walk", "run"], "time_offset": {"min": 1, "max": 2}, "speed": {"min": 0.5, "max": 0.6}},
      "palettes": [{"torso": [1, 0, 0]}, {"torso": [0, 1, 0]}]})",
                      "s.json");
  std::set<uint32_t> clips, palettes;
  for (const auto &i : s.instances) {
    EXPECT_GE(i.timeOffset, 1);
    EXPECT_LE(i.timeOffset, 2);
    EXPECT_GE(i.speed, 0.5);
    EXPECT_LE(i.speed, 0.6);
    clips.insert(i.clip);
    palettes.insert(i.palette);
  }
  EXPECT_EQ(clips.size(), 2u);
  EXPECT_EQ(palettes.size(), 2u);
}

TEST(Scene, OutfitsFixedWeightedOrInTurn) {
  auto fixed = parseScene(
      R"({"packs": [{"path": "a"}], "instances": {"count": 4, "outfit": "dress"}})", "s.json");
  EXPECT_EQ(fixed.outfitNames, std::vector<std::string>{"dress"});
  for (const auto &i : fixed.instances)
    EXPECT_EQ(i.outfit, 0u);
  EXPECT_EQ(parseScene(kMinimal, "s.json").outfitNames, std::vector<std::string>{""});

  auto weighted = parseScene(R"({"packs": [{"path": "a"}], "instances": {"count": 2000,
      "outfit": {"dress": 3, "jumper_skirt": 1, "none": 0}}})",
                             "s.json");
  EXPECT_EQ(weighted.outfitNames, (std::vector<std::string>{"dress", "jumper_skirt", "none"}));
  size_t counts[3] = {};
  for (const auto &i : weighted.instances)
    ++counts[i.outfit];
  EXPECT_EQ(counts[2], 0u);
  EXPECT_NEAR(double(counts[0]) / 2000.0, 0.75, 0.05);

  auto cycle = parseScene(R"({"packs": [{"path": "a"}], "instances": {"count": 5,
      "outfit": ["a", "b"], "outfit_order": "cycle"}})",
                          "s.json");
  std::vector<uint32_t> order;
  for (const auto &i : cycle.instances)
    order.push_back(i.outfit);
  EXPECT_EQ(order, (std::vector<uint32_t>{0, 1, 0, 1, 0}));

  // Outfits leave the other draws alone: the same instances as without them.
  auto plain = parseScene(R"({"packs": [{"path": "a"}], "instances": {"count": 9,
      "clip": ["x", "y"], "placement": {"type": "random"}}})",
                          "s.json");
  auto dressed = parseScene(R"({"packs": [{"path": "a"}], "instances": {"count": 9,
      "clip": ["x", "y"], "placement": {"type": "random"}, "outfit": ["a", "b"],
      "outfit_order": "cycle"}})",
                            "s.json");
  for (size_t k = 0; k < 9; ++k) {
    EXPECT_EQ(plain.instances[k].clip, dressed.instances[k].clip);
    EXPECT_EQ(plain.instances[k].position, dressed.instances[k].position);
  }

  for (const char *bad : {R"("outfit": 3)", R"("outfit": {"a": 0})", R"("outfit": [])",
                          R"("outfit_order": "sorted")"}) {
    std::string text = std::string(R"({"packs": [{"path": "a"}], "instances": {)") + bad + "}}";
    EXPECT_NE(errorOf(text).find("s.json:1:"), std::string::npos) << bad;
  }
}

TEST(Scene, CameraPathInterpolatesAndLoops) {
  auto s = parseScene(R"({"packs": [{"path": "a"}], "instances": {},
      "camera": {"path": [{"time": 0, "position": [0, 0, 0], "target": [0, 0, -1]},
                          {"time": 2, "position": [4, 0, 0], "target": [0, 0, -1]}]}})",
                      "s.json");
  glm::dvec3 eye, target;
  s.camera.at(1, eye, target);
  EXPECT_DOUBLE_EQ(eye.x, 2);
  s.camera.at(3, eye, target); // looped: t = 1
  EXPECT_DOUBLE_EQ(eye.x, 2);
}

TEST(Scene, ErrorsGiveLineAndColumn) {
  EXPECT_EQ(errorOf("{\n  \"packs\": [\n    {\"path\": \"a\",}\n  ]\n}").rfind("s.json:3:", 0), 0u);
  std::string e = errorOf("{\"packs\": [{\"path\": \"a\"}],\n \"instances\": {\"count\": -3}}");
  EXPECT_NE(e.find("s.json:2:"), std::string::npos) << e;
  EXPECT_NE(e.find("/instances/count: value -3"), std::string::npos) << e;
  e = errorOf(
      "{\"packs\": [{\"path\": \"a\"}], \"instances\": {\"placement\": {\"type\": \"spiral\"}}}");
  EXPECT_NE(e.find("unknown placement 'spiral'"), std::string::npos) << e;
  e = errorOf("{\"packs\": [], \"instances\": {}}");
  EXPECT_NE(e.find("/packs: expected a non-empty list"), std::string::npos) << e;
  e = errorOf(R"({"packs": [{"path": "a"}], "instances": {}, "palettes": [{"torso": [2, 0, 0]}]})");
  EXPECT_NE(e.find("colour components must be in [0, 1]"), std::string::npos) << e;
  e = errorOf(R"({"packs": [{"path": "a"}], "instances": {"pack": "b"}})");
  EXPECT_NE(e.find("no pack named \"b\""), std::string::npos) << e;
  // A number past a double's range (the manifest fuzzer's finding: it escaped as the JSON
  // library's own exception).
  e = errorOf("{\"packs\": [{\"path\": \"a\"}],\n \"instances\": {\"count\": 7e777}}");
  EXPECT_EQ(e, "s.json:2:25: a number out of range: 7e777");
  // Names of another type than a string (the scene fuzzer's finding), each where it is.
  e = errorOf(R"({"packs": [{"path": "a"}], "instances": {"pack": ["walk", "run"]}})");
  EXPECT_NE(e.find("/instances/pack: expected"), std::string::npos) << e;
  e = errorOf(R"({"packs": [{"path": "a", "name": 3}], "instances": {}})");
  EXPECT_NE(e.find("/packs/name: expected"), std::string::npos) << e;
  e = errorOf(R"({"packs": [{"path": "a"}], "instances": {"placement": 4}})");
  EXPECT_NE(e.find("/instances/placement: expected an object"), std::string::npos) << e;
}

} // namespace

namespace {
TEST(Scene, EverySampleSceneParses) {
  size_t n = 0;
  for (const auto &e :
       std::filesystem::directory_iterator(std::string(CROWD_SOURCE_DIR) + "/samples/scenes")) {
    SCOPED_TRACE(e.path().string());
    EXPECT_NO_THROW(runtime::loadScene(e.path().string()));
    ++n;
  }
  EXPECT_GE(n, 3u);
}

// A scene is read only where it is a regular file under the input bound: /dev/zero, read whole
// before, grew until memory ran out.
TEST(Scene, LoadRefusesWhatIsNotARegularFile) {
  try {
    runtime::loadScene("/dev/zero");
    ADD_FAILURE() << "/dev/zero loaded";
  } catch (const Error &e) {
    EXPECT_EQ(std::string(e.what()),
              "scene /dev/zero: not a regular file (a device): nothing read");
  }
}
} // namespace

namespace {
std::string thisProcessId() { return std::to_string(::getpid()); }
} // namespace

// The helper the determinism tests use fails where a result depends on the process.
TEST(FreshProcess, AResultThatDependsOnTheProcessFails) {
  if (test::inFreshProcess()) {
    test::sameInAFreshProcess(thisProcessId);
    return;
  }
  EXPECT_NONFATAL_FAILURE(test::sameInAFreshProcess(thisProcessId), "the results differ");
}
