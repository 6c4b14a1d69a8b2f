// The error budget of the animation bake: what it chooses on a real-sized character, what a
// forced --fps or --precision leaves to it, and the clips it cannot or can only just meet.
#include <cmath>
#include <map>

#include <gtest/gtest.h>

#include "crowd/bake/anim_bake.h"
#include "crowd/bake/import.h"
#include "crowd/formats/chunks.h"
#include "crowd/formats/error.h"
#include "gltf_writer.h"
#include "sample_character.h"

using namespace crowd;

namespace {

// These tests measure the animation texture (the reference encoding): every bake stores it.
AnimBakeOptions textureBake() {
  AnimBakeOptions o;
  o.store = "texture";
  return o;
}

AnimBakeResult bake(const Character &c, AnimBakeOptions o = textureBake()) {
  Reporter r;
  r.quiet = true;
  return bakeAnimation(c, o, r);
}

Character quadWith(const std::string &name, const std::function<void(test::GltfBuilder &)> &add) {
  test::GltfBuilder b;
  b.skinnedQuad();
  add(b);
  Reporter r;
  r.quiet = true;
  return importGltf(b.write(test::tempDir("budget_" + name), name), {}, r);
}

double worstMm(const AnimBakeResult &r) {
  double worst = 0;
  for (const auto &a : r.accuracy[r.baked].clips)
    worst = std::max(worst, a.maxAnyTime() * r.mmPerUnit);
  return worst;
}

TEST(AnimBudget, TheFewestBytesThatMeetTheBudgetOnEveryClip) {
  const AnimBakeResult r = bake(test::sampleHumanoid());
  ASSERT_TRUE(r.budget.met);
  EXPECT_LE(worstMm(r), 1.0);
  EXPECT_LE(r.accuracy[r.baked].precision.bytesPerJointPerFrame(), 32);
  // Per precision, each clip's lowest meeting rate; the chosen precision costs the fewest bytes.
  std::map<std::string, uint64_t> bytes;
  std::map<std::string, bool> meets;
  for (const auto &p : precisions())
    meets[p.name] = true;
  for (size_t ci = 0; ci < r.budget.clips.size(); ++ci) {
    const ClipBudget &cb = r.budget.clips[ci];
    std::map<std::string, const BudgetOption *> first;
    for (const auto &o : cb.tried) {
      EXPECT_TRUE(o.fps > 0 && o.bytes > 0) << cb.clip;
      if (o.meets && !first.count(o.precision))
        first[o.precision] = &o;
    }
    for (const auto &p : precisions()) {
      if (!first.count(p.name))
        meets[p.name] = false;
      else
        bytes[p.name] += first[p.name]->bytes;
    }
    ASSERT_TRUE(first.count(r.budget.precision)) << cb.clip;
    EXPECT_DOUBLE_EQ(cb.fps, first[r.budget.precision]->fps) << cb.clip;
    EXPECT_FLOAT_EQ(r.pack.clips[ci].fps, float(cb.fps)) << cb.clip;
  }
  for (const auto &p : precisions())
    if (meets[p.name]) {
      EXPECT_LE(bytes[r.budget.precision], bytes[p.name]) << p.name;
    }
  // A tighter budget never costs fewer bytes (one clip, to keep the test short).
  AnimBakeOptions tight = textureBake();
  tight.errorBudgetMm = 0.25;
  tight.clip = "walk";
  const AnimBakeResult t = bake(test::sampleHumanoid(), tight);
  EXPECT_GE(t.pack.clips[0].frameCount * t.accuracy[t.baked].precision.bytesPerJointPerFrame(),
            r.pack.clips[0].frameCount * r.accuracy[r.baked].precision.bytesPerJointPerFrame());
  EXPECT_LE(worstMm(t), 0.25);
}

TEST(AnimBudget, AForcedRateOrPrecisionNarrowsTheSearch) {
  const Character c = quadWith("forced", [](test::GltfBuilder &b) {
    b.animation("lift", 1, "translation", {0, 0.31f, 1}, {0, 0.5f, 0, 0, 1.5f, 0, 0, 0.5f, 0});
  });
  AnimBakeOptions at30 = textureBake();
  at30.fps = 30;
  const AnimBakeResult r30 = bake(c, at30);
  for (const auto &o : r30.budget.clips.at(0).tried)
    EXPECT_NEAR(o.fps, 30, 1e-9);
  AnimBakeOptions qts = textureBake();
  qts.precision = "qts";
  const AnimBakeResult q = bake(c, qts);
  EXPECT_EQ(q.budget.precision, "qts");
  for (const auto &o : q.budget.clips.at(0).tried)
    EXPECT_EQ(o.precision, "qts");
  AnimBakeOptions both = at30;
  both.precision = "half";
  const AnimBakeResult h = bake(c, both);
  EXPECT_TRUE(h.budget.clips.at(0).tried.empty());
  EXPECT_EQ(h.accuracy[h.baked].precision.name, "half");
  // The key at 0.31 s falls between 30 fps frames: the blend cuts its corner, over budget.
  EXPECT_FALSE(h.budget.met);
  AnimBakeOptions source = both;
  source.fps = AnimBakeOptions::kFpsSource;
  source.precision = "auto";
  const ClipBudget onKeys = bake(c, source).budget.clips.at(0);
  EXPECT_NEAR(onKeys.sourceFps, 1 / 0.31, 1e-4); // keys are single precision
  EXPECT_NEAR(onKeys.fps, 3, 1e-9);              // 1 s: 3 whole intervals
  for (const auto &o : onKeys.tried)
    EXPECT_NEAR(o.fps, 3, 1e-9);
}

// Failure modes: each bakes, and the report says whether the budget holds.
TEST(AnimBudget, AHalfTurnBetweenTwoKeysMeetsTheBudget) {
  const Character c = quadWith("halfturn", [](test::GltfBuilder &b) {
    b.animation("spin", 0, "rotation", {0, 1}, {0, 0, 0, 1, 0, 0, 1, 0}); // 0 to 180 degrees
  });
  const AnimBakeResult r = bake(c);
  EXPECT_TRUE(r.budget.met);
  EXPECT_LE(worstMm(r), 1.0);
}

TEST(AnimBudget, TwoKeysAtOneTimeAreAStepNoRateMeets) {
  test::GltfBuilder b;
  b.skinnedQuad();
  b.animation("jump", 1, "translation", {0, 0.5f, 0.5f, 1},
              {0, 0.5f, 0, 0, 0.5f, 0, 0, 1.5f, 0, 0, 1.5f, 0});
  Reporter rep;
  rep.quiet = true;
  const Character c = importGltf(b.write(test::tempDir("budget_step"), "step"), {}, rep);
  bool step = false; // read as a step, with a warning
  for (const auto &w : rep.warnings())
    step = step || w.code == "keys_at_one_time";
  EXPECT_TRUE(step);
  const AnimBakeResult r = bakeAnimation(c, textureBake(), rep);
  EXPECT_FALSE(r.budget.met);
  // The vertex that follows joint b by half jumps 0.5 units (900 mm at 1.8 m): a blend across
  // the step errs by half that at the mid-frame, and up to all of it just before the step.
  EXPECT_GE(worstMm(r), 450 * 0.99);
  EXPECT_LE(worstMm(r), 900 * 1.01);
  bool warned = false;
  for (const auto &w : rep.warnings())
    warned = warned || w.code == "error_budget_not_met";
  EXPECT_TRUE(warned);
}

TEST(AnimBudget, AOneKeyClipIsOneFrame) {
  const Character c = quadWith("onekey", [](test::GltfBuilder &b) {
    b.animation("pose", 1, "translation", {0.5f}, {0, 1, 0});
  });
  const AnimBakeResult r = bake(c);
  ASSERT_EQ(r.pack.clips.size(), 1u);
  EXPECT_EQ(r.pack.clips[0].frameCount, 1u);
  EXPECT_TRUE(r.budget.met);
  EXPECT_LE(worstMm(r), 1e-3);
}

TEST(AnimBudget, AClipOf100000KeysBakesAtALowRate) {
  const Character c = quadWith("manykeys", [](test::GltfBuilder &b) {
    std::vector<float> times, values;
    for (int k = 0; k < 100000; ++k) { // 100 s keyed at 1,000 fps: a slow sway
      times.push_back(float(k) * 1e-3f);
      values.insert(values.end(), {0.1f * float(std::sin(k * 1e-3)), 0.5f, 0});
    }
    b.animation("sway", 1, "translation", times, values);
  });
  const AnimBakeResult r = bake(c);
  EXPECT_TRUE(r.budget.met);
  EXPECT_LE(r.pack.clips.at(0).frameCount, 100 * 30 + 1u);
  EXPECT_NEAR(r.budget.clips.at(0).sourceFps, 1000, 1);
}

// The quaternion encodings carry one scale per joint: a joint that stretches falls back to
// matrix rows, and only it (and the joints it carries).
TEST(AnimBudget, ANonUniformScaleFallsBackToMatricesForItsJointsOnly) {
  const Character c = quadWith("stretch", [](test::GltfBuilder &b) {
    const int anim = b.animation("stretch", 1, "scale", {0, 1}, {1, 1, 1, 2, 1, 1});
    b.channel(anim, 0, "rotation", {0, 1}, {0, 0, 0, 1, 0, 0, 0.38268343f, 0.92387953f});
  });
  const AnimBakeResult r = bake(c);
  EXPECT_TRUE(r.budget.met);
  EXPECT_LE(worstMm(r), 1.0);
  EXPECT_EQ(r.budget.matrixJoints, std::vector<uint32_t>{1}); // "b"; "a" only turns
  ASSERT_EQ(r.budget.precision.rfind("qts", 0), 0u) << r.budget.precision;
  const pack::AnimationTexture &t = r.pack.animation;
  EXPECT_EQ(t.encoding, pack::JointEncoding::QtsWithMatrices);
  EXPECT_FALSE(t.isMatrix(0));
  EXPECT_TRUE(t.isMatrix(1));
  EXPECT_EQ(t.frameTexels(), 2u + 3u);
  // It round-trips through the chunk.
  const auto decoded = pack::decodeAnimationTexture(pack::encode(t), "test");
  EXPECT_EQ(decoded.matrixJoints, t.matrixJoints);
  EXPECT_EQ(decoded.texels, t.texels);
  // A damaged list is a clear error: none, out of range, not ascending, or a cut chunk.
  for (const std::vector<uint32_t> &bad :
       {std::vector<uint32_t>{}, std::vector<uint32_t>{2}, std::vector<uint32_t>{1, 1}}) {
    pack::AnimationTexture d = t;
    d.matrixJoints = bad;
    EXPECT_THROW(pack::decodeAnimationTexture(pack::encode(d), "test"), Error) << bad.size();
  }
  const auto bytes = pack::encode(t);
  for (size_t cut : {size_t(30), size_t(36), bytes.size() - 1})
    EXPECT_THROW(pack::decodeAnimationTexture({bytes.data(), cut}, "test"), Error) << cut;

  // A stretching root carries its child: both joints fall back, and the qts options still meet
  // the budget.
  const Character root = quadWith("stretch_root", [](test::GltfBuilder &b) {
    b.animation("stretch", 0, "scale", {0, 1}, {1, 1, 1, 2, 1, 1});
  });
  const AnimBakeResult all = bake(root);
  EXPECT_TRUE(all.budget.met);
  EXPECT_EQ(all.budget.matrixJoints, (std::vector<uint32_t>{0, 1}));
  for (const auto &o : all.budget.clips.at(0).tried)
    if (o.precision == "qts") {
      EXPECT_TRUE(o.meets) << o.fps;
    }
}

} // namespace
