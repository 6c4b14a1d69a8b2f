// Morph targets: read from glTF, evaluated exactly (morph, then skin), baked as offsets and
// per-frame slots, and played by the CPU mirror of the shader with the error reported like the
// skinning's. Failure modes: weights animated without targets, more targets active than slots.
#include <filesystem>

#include <gtest/gtest.h>

#include "crowd/bake/anim_bake.h"
#include "crowd/bake/evaluate.h"
#include "crowd/bake/import.h"
#include "crowd/bake/lod_bake.h"
#include "crowd/formats/error.h"
#include "gltf_writer.h"
#include "skip.h"

using namespace crowd;

namespace {

bool warned(const Reporter &r, const std::string &code) {
  for (const auto &w : r.warnings())
    if (w.code == code)
      return true;
  return false;
}

std::string morphedQuad(const std::string &dir, int targets) {
  test::GltfBuilder g;
  g.morphedQuad(targets);
  return g.write(dir, "morphed" + std::to_string(targets));
}

// Both encodings: these tests measure the texture's morph frames and the tracks played with them.
AnimBakeResult bake(const Character &c, Reporter &r) {
  AnimBakeOptions o;
  o.store = "both";
  return bakeAnimation(c, o, r);
}

} // namespace

TEST(Morph, TheReferenceMorphsBeforeItSkins) {
  const auto dir = test::tempDir("morph_reference");
  Reporter r;
  r.quiet = true;
  const Character c = importGltf(morphedQuad(dir, 2), {}, r);
  ASSERT_EQ(c.mesh.morphs.size(), 2u);
  ASSERT_EQ(c.morphGroups.size(), 1u);
  for (const auto &w : r.warnings())
    EXPECT_EQ(w.code.find("morph"), std::string::npos) << w.message;
  // At t = 0.5 both weights are 0.5: vertex 3 (1, 1, 0) rises by 0.5 * (1 + 2) cm before
  // skinning. Joint b is turned 45 degrees about z at (0, 0.5, 0), and vertex 3 follows b and a
  // by 0.25 and 0.75.
  const auto weights = morphWeights(c, &c.clips[0], 0.5);
  EXPECT_NEAR(weights[0], 0.5, 1e-9);
  EXPECT_NEAR(weights[1], 0.5, 1e-9);
  const auto p = posedPositions(c, &c.clips[0], 0.5);
  const glm::dvec3 morphed(1, 1.015, 0), pivot(0, 0.5, 0);
  const double angle = std::acos(-1.0) / 4, cs = std::cos(angle), sn = std::sin(angle);
  const glm::dvec3 d = morphed - pivot;
  const glm::dvec3 turned = pivot + glm::dvec3(cs * d.x - sn * d.y, sn * d.x + cs * d.y, 0);
  const glm::dvec3 expected = 0.75 * morphed + 0.25 * turned;
  EXPECT_NEAR(glm::length(p[3] - expected), 0.0, 1e-6);
}

TEST(Morph, SkinnedMorphsBakeWithinTheBudgetAtAnyTime) {
  const auto dir = test::tempDir("morph_skinned");
  Reporter r;
  r.quiet = true;
  const Character c = importGltf(morphedQuad(dir, 2), {}, r);
  const auto result = bake(c, r);
  ASSERT_TRUE(result.pack.morphs.has_value());
  EXPECT_EQ(result.pack.morphs->frameCount(), result.pack.animation.frameCount);
  const auto &clip = result.accuracy[result.baked].clips.at(0);
  EXPECT_LE(clip.maxAnyTime() * result.mmPerUnit, 1.0);
  EXPECT_GT(clip.maxAnyTime(), 0.0); // measured, not skipped
  ASSERT_EQ(result.tracks.size(), 1u);
  EXPECT_LE(result.tracks[0].maxAnyTimeMm(), 1.0);
  EXPECT_GT(result.tracks[0].maxAnyTimeMm(), 0.0);
  // The chunk survives the pack's round trip and its cross-checks.
  const auto bytes = pack::packBytes(result.pack);
  const auto back = pack::loadAnimationPack(pack::Reader(bytes, "morphs"));
  ASSERT_TRUE(back.morphs.has_value());
  EXPECT_EQ(back.morphs->offsets, result.pack.morphs->offsets);
}

TEST(Morph, LodReordersTheOffsetsWithTheVertices) {
  const auto dir = test::tempDir("morph_lod");
  Reporter r;
  r.quiet = true;
  Character c = importGltf(morphedQuad(dir, 2), {}, r);
  const auto before = posedPositions(c, &c.clips[0], 1.0);
  LodResult details;
  applyLod(c, {}, r, &details);
  const auto after = posedPositions(c, &c.clips[0], 1.0);
  ASSERT_EQ(after.size(), details.order.size());
  for (size_t k = 0; k < after.size(); ++k)
    EXPECT_NEAR(glm::length(after[k] - before[details.order[k]]), 0.0, 1e-12);
}

TEST(Morph, WeightsWithoutTargetsAreReportedAndIgnored) {
  const auto dir = test::tempDir("morph_stray");
  test::GltfBuilder g;
  const int node = g.skinnedQuad();
  g.animation("stray", node, "weights", {0, 1}, {0, 1});
  Reporter r;
  r.quiet = true;
  const Character c = importGltf(g.write(dir, "stray"), {}, r);
  EXPECT_TRUE(warned(r, "morph_weights_without_targets"));
  EXPECT_TRUE(c.clips.empty()); // its one channel went: nothing animates
  const auto result = bake(c, r);
  EXPECT_FALSE(result.pack.morphs.has_value());
}

TEST(Morph, MoreTargetsThanSlotsDropTheLeastMovingAndSayHowFar) {
  const auto dir = test::tempDir("morph_slots");
  Reporter r;
  r.quiet = true;
  const Character c = importGltf(morphedQuad(dir, 10), {}, r);
  const auto result = bake(c, r);
  EXPECT_TRUE(warned(r, "morph_slots_full"));
  EXPECT_EQ(result.morphOverflow.mostActive, 10u);
  // At t = 1 every weight is 1: the two smallest targets (1 and 2 cm) are dropped, 3 cm up in
  // all, and the report's error at frame times says so: vertex 3 follows joint a (still) by 0.75
  // and joint b (turned 90 degrees) by 0.25, so the missing 3 cm shows as 3 * |(0.75, 0.25)| cm.
  EXPECT_NEAR(result.morphOverflow.largestDropped, 0.02, 1e-6);
  const auto &clip = result.accuracy[result.baked].clips.at(0);
  EXPECT_NEAR(clip.maxAtFrames, 0.03 * std::sqrt(0.75 * 0.75 + 0.25 * 0.25), 1e-5);
}

TEST(Morph, MismatchedTargetsAreClearErrors) {
  const auto dir = test::tempDir("morph_bad");
  test::GltfBuilder g;
  g.skinnedQuad();
  g.morphTargets(0, {std::vector<float>(9, 0.0f)}); // 3 offsets for 4 vertices
  Reporter r;
  r.quiet = true;
  try {
    importGltf(g.write(dir, "short"), {}, r);
    FAIL() << "a target shorter than its primitive was accepted";
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("morph target 0 POSITION"), std::string::npos) << e.what();
  }
  test::GltfBuilder h;
  const int node = h.skinnedQuad();
  h.morphTargets(0, {std::vector<float>(12, 0.0f)});
  h.animation("wide", node, "weights", {0, 1}, {0, 1, 0, 1}); // 2 values per key for 1 target
  try {
    importGltf(h.write(dir, "wide"), {}, r);
    FAIL() << "a weights channel of the wrong width was accepted";
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("output"), std::string::npos) << e.what();
  }
}

TEST(Morph, AnimatedMorphCubeBakesAndPlays) {
  const std::string file =
      std::string(CROWD_SHARED_ASSETS) + "/AnimatedMorphCube/AnimatedMorphCube.glb";
  if (!std::filesystem::exists(file))
    CROWD_SKIP("shared assets absent: " << file);
  Reporter r;
  r.quiet = true;
  const Character c = importGltf(file, {}, r);
  EXPECT_FALSE(c.skinned); // a morph-only mesh: no skin
  const auto result = bake(c, r);
  ASSERT_TRUE(result.pack.morphs.has_value());
  const auto &clip = result.accuracy[result.baked].clips.at(0);
  EXPECT_LE(clip.maxAnyTime() * result.mmPerUnit, 1.0);
  // The morphs move it: some vertex leaves its bind position by over a tenth of the diagonal.
  double moved = 0;
  const auto rest = posedPositions(c, nullptr, 0);
  for (double t = 0; t < c.clips[0].end; t += 0.1) {
    const auto p = posedPositions(c, &c.clips[0], t);
    for (size_t v = 0; v < p.size(); ++v)
      moved = std::max(moved, glm::length(p[v] - rest[v]));
  }
  EXPECT_GT(moved, 0.1 * result.diagonal);
}

// A morph clip whose weights step (STEP keys, a 10 cm target, the joints still): the pack holds
// morph weights per clip frame and the player blends between frames, so a step is smeared over a
// frame at any rate. Not met, and said so: the error, from the seeded random times just before a
// step, is over half the target's offset (issue 77's morph weights as tracks would hold it).
TEST(Morph, SteppedWeightsMissTheBudgetAndSaySo) {
  const auto dir = test::tempDir("morph_step");
  test::GltfBuilder g;
  const int node = g.skinnedQuad();
  std::vector<float> offsets(12, 0.0f);
  offsets[10] = 0.1f;
  g.morphTargets(0, {offsets});
  g.animation("blink", node, "weights", {0, 1, 2, 3}, {0, 1, 0, 1}, "STEP");
  Reporter r;
  r.quiet = true;
  const Character c = importGltf(g.write(dir, "stepped"), {}, r);
  const auto result = bakeAnimation(c, {}, r);
  ASSERT_TRUE(result.pack.morphs.has_value());
  ASSERT_EQ(result.tracks.size(), 1u);
  const double stepMm = 0.1 * result.mmPerUnit, mm = result.tracks[0].maxAnyTimeMm();
  std::printf("stepped weights: stored %s, tracks %.3f mm of a %.1f mm step\n",
              result.stored.c_str(), mm, stepMm);
  EXPECT_FALSE(result.tracks[0].met);
  EXPECT_TRUE(warned(r, "error_budget_not_met"));
  EXPECT_GT(mm, 0.5 * stepMm);
  EXPECT_LE(mm, stepMm * (1 + 1e-6));
}
