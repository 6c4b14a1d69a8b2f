#include <filesystem>
#include <map>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "crowd/bake/anim_bake.h"
#include "crowd/bake/evaluate.h"
#include "crowd/bake/import.h"
#include "crowd/bake/preview.h"
#include "crowd/formats/error.h"
#include "crowd/runtime/texture_skinning.h"
#include "fresh_process.h"
#include "gltf_writer.h"
#include "real_models.h"
#include "sample_character.h"

using namespace crowd;

namespace {

// These tests measure the animation texture (the reference encoding): every bake stores it.
AnimBakeOptions textureBake() {
  AnimBakeOptions o;
  o.store = "texture";
  return o;
}

const Character &humanoid() { return test::sampleHumanoid(); }

// The matrix layout at a fixed rate, which the layout tests below count in.
AnimBakeOptions float30() {
  AnimBakeOptions o = textureBake();
  o.fps = 30;
  o.precision = "float";
  return o;
}

AnimBakeResult bake(const Character &c, AnimBakeOptions o = textureBake()) {
  Reporter r;
  r.quiet = true;
  return bakeAnimation(c, o, r);
}

TEST(Samples, HumanoidHasWhatLaterBakesNeed) {
  const Character &c = humanoid();
  EXPECT_GE(c.jointCount(), 20u);
  EXPECT_GE(c.mesh.indices.size() / 3, 3000u);
  std::vector<std::string> parts;
  for (const auto &p : c.mesh.parts)
    parts.push_back(p.name);
  EXPECT_EQ(parts, (std::vector<std::string>{"head", "torso", "arms", "hands", "legs", "feet"}));
  ASSERT_EQ(c.clips.size(), 3u);
  EXPECT_EQ(c.clips[0].name, "walk");
  EXPECT_EQ(c.clips[1].name, "run");
  EXPECT_EQ(c.clips[2].name, "idle");
  EXPECT_FALSE(c.mesh.uvs.empty());
  ASSERT_TRUE(c.diffuse.has_value());
  EXPECT_EQ(c.diffuse->width, 256);
  EXPECT_EQ(c.diffuse->rgba.size(), 256u * 256 * 4);
}

TEST(AnimBake, FrameTimesMeetTheFp32TargetAndLoopsClose) {
  const Character &c = humanoid();
  AnimBakeResult r = bake(c, float30());
  const auto &acc = r.accuracy[r.baked];
  EXPECT_EQ(acc.precision.name, "float");
  for (const auto &clip : acc.clips) {
    EXPECT_LE(clip.maxAtFrames, 1e-5 * r.diagonal) << clip.clip;
    // Forced to 30 fps (not the budget's rate): the run errs 9.77 mm between frames.
    EXPECT_LE(clip.maxAtMidframes, 1e-2 * r.diagonal) << clip.clip;
  }
  for (const auto &clip : r.pack.clips) {
    EXPECT_TRUE(clip.loop) << clip.name;
    // The closing frame is stored and equals the first, so wrapping interpolates exactly.
    for (uint32_t j = 0; j < r.pack.animation.jointCount; ++j)
      for (uint32_t k = 0; k < 3; ++k) {
        auto [x0, y0] = r.pack.animation.texelOf(clip.firstFrame, j);
        auto [x1, y1] = r.pack.animation.texelOf(clip.firstFrame + clip.frameCount - 1, j);
        auto a = r.pack.animation.texel(x0 + k, y0), b = r.pack.animation.texel(x1 + k, y1);
        for (int i = 0; i < 4; ++i)
          EXPECT_NEAR(a[size_t(i)], b[size_t(i)], 1e-5f);
      }
  }
  EXPECT_EQ(r.pack.clips[0].frameCount, 31u); // 1 s at 30 fps, closing frame included
  EXPECT_EQ(r.pack.clips[1].frameCount, 22u); // 0.7 s: 21 intervals
}

TEST(AnimBake, RowsWrapWithoutSplittingAFrame) {
  const Character &c = humanoid();
  AnimBakeOptions o = float30();
  o.maxWidth = 22 * 3 * 5 + 17; // five frames fit, with room to spare
  AnimBakeResult r = bake(c, o);
  const auto &t = r.pack.animation;
  EXPECT_EQ(t.framesPerRow, 5u);
  EXPECT_EQ(t.width, 22u * 3 * 5);
  EXPECT_EQ(t.height, (t.frameCount + 4) / 5);
  for (uint32_t f = 0; f < t.frameCount; ++f) {
    auto [x0, y0] = t.texelOf(f, 0);
    auto [x1, y1] = t.texelOf(f, 21);
    EXPECT_EQ(y0, y1);
    EXPECT_LT(x1 + 2, t.width);
  }
  for (const auto &clip : r.accuracy[r.baked].clips)
    EXPECT_LE(clip.maxAtFrames, 1e-5 * r.diagonal);
}

TEST(AnimBake, BytesDoNotDependOnThreadCountOrProcess) {
  auto packs = [](int threads) { // the budget's search included
    AnimBakeOptions o = textureBake();
    o.clip = "run";
    o.threads = threads;
    std::string bytes;
    for (std::string p : {"auto", "qts-half"}) {
      o.precision = p;
      const auto b = pack::packBytes(bake(humanoid(), o).pack);
      bytes.append(b.begin(), b.end());
    }
    return bytes;
  };
  const auto seven = test::sameInAFreshProcess([&] { return packs(7); });
  if (!seven)
    return;
  EXPECT_EQ(packs(1), *seven);
}

TEST(AnimBake, CompactPrecisionsCostFewerBytesAndReportTheirError) {
  AnimBakeResult r = bake(humanoid());
  ASSERT_EQ(r.accuracy.size(), 4u);
  EXPECT_EQ(r.accuracy[0].precision.bytesPerJointPerFrame(), 48);
  EXPECT_EQ(r.accuracy[1].precision.bytesPerJointPerFrame(), 24);
  EXPECT_EQ(r.accuracy[2].precision.bytesPerJointPerFrame(), 32);
  EXPECT_EQ(r.accuracy[3].precision.bytesPerJointPerFrame(), 16);
  for (const auto &pa : r.accuracy)
    for (const auto &clip : pa.clips) {
      // Half precision keeps about 3 decimal digits: at most 3.16e-4 of the diagonal at frames
      // (0.60 mm, run in half), float and qts 1.54e-7 (float32 rounding): each held at twice.
      const bool half = pa.precision.name.find("half") != std::string::npos;
      EXPECT_LE(clip.maxAtFrames, (half ? 6.4e-4 : 3.1e-7) * r.diagonal)
          << pa.precision.name << " " << clip.clip;
      EXPECT_GT(clip.maxAtFrames, 0.0);
    }
}

TEST(AnimBake, BoundingSphereCoversEveryFrameAndMidFrame) {
  const Character &c = humanoid();
  AnimBakeResult r = bake(c);
  const auto &s = r.pack.mesh.boundingSphere;
  glm::vec3 centre(s[0], s[1], s[2]);
  for (const auto &clip : r.pack.clips)
    for (uint32_t f = 0; f < clip.frameCount; ++f)
      for (float alpha : {0.0f, 0.25f, 0.5f})
        for (uint32_t v = 0; v < c.mesh.vertexCount(); v += 7) {
          glm::vec3 p = runtime::skinVertex(r.pack.animation, r.pack.skin, clip, f, alpha, v,
                                            c.mesh.positions[v]);
          ASSERT_LE(glm::length(p - centre), s[3]) << clip.name << " frame " << f;
        }
}

TEST(AnimBake, UnknownClipListsTheClips) {
  AnimBakeOptions o = textureBake();
  o.clip = "dance";
  try {
    bake(humanoid(), o);
    FAIL();
  } catch (const Error &e) {
    EXPECT_STREQ(e.what(), "no clip named 'dance' (clips: walk, run, idle)");
  }
}

TEST(TextureSkinning, FrameAtWrapsLoopsAndClampsOthers) {
  pack::Clip loop{"l", 10, 0, 0, 11, true}, once{"o", 10, 0, 0, 11, false};
  uint32_t f;
  float a;
  runtime::frameAt(loop, 1.25f, f, a); // 12.5 frames on a 10-interval loop: frame 2.5
  EXPECT_EQ(f, 2u);
  EXPECT_NEAR(a, 0.5f, 1e-5f);
  runtime::frameAt(once, 1.25f, f, a);
  EXPECT_EQ(f, 10u);
  EXPECT_EQ(a, 0.0f);
  // A loop's end is its closing frame (the source's last key), not the first, which matches it
  // only within the loop test's tolerance: Stag's Eating loops with its antlers 0.124 mm apart
  // between its ends, and showed the first frame at its last key's time.
  runtime::frameAt(loop, 1.0f, f, a);
  EXPECT_EQ(f, 10u);
  EXPECT_EQ(a, 0.0f);
  runtime::frameAt(loop, 2.0f, f, a); // past the end it wraps: the second end is the first frame
  EXPECT_EQ(f, 0u);
  runtime::frameAt(loop, -0.25f, f, a); // and before the start
  EXPECT_EQ(f, 7u);
  EXPECT_NEAR(a, 0.5f, 1e-5f);
}

// Turns of -100 and 170 degrees about z: read from their matrices, their quaternions (xyzw:
// 0, 0, -0.77, 0.64 and 0, 0, 0.996, 0.087) lie on opposite hemispheres. Halfway through a
// crossfade the joint must take the short way round, through -145 degrees, not the long way
// through 35.
TEST(TextureSkinning, CrossfadeBlendsTheShortWayRound) {
  auto turn = [](float degrees) {
    return runtime::toRows(glm::rotate(glm::mat4(1), glm::radians(degrees), glm::vec3(0, 0, 1)));
  };
  const runtime::JointRows mid = runtime::blendJoints(turn(-100), turn(170), 0.5f);
  const runtime::JointRows half = turn(-145);
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 4; ++k)
      EXPECT_NEAR(mid[size_t(r)][k], half[size_t(r)][k], 1e-5f) << r << " " << k;
}

// Every real glTF character (test::realModels: ../shared/assets/gltf and the Blender exports):
// held to the fp32 target at frame times when stored as float matrices, and within the default
// error budget at any time: as a texture where one of kRateLadder's rates meets it, and by the
// budget's own choice of store always.
// The texture's one miss: Dragon_Evolved's Punch (30 fps keys, a wing turning some 900 degrees a
// second) errs 1.13 mm between frames even at 240 fps, the ladder's top, where blending joint
// matrices linearly shortens the wing; the default bake stores it as joint tracks, within 1 mm.
// The test holds that clip to its top rate and 1.2 mm, and the default bake of the model to the
// budget (animation issue: a texture rate past the ladder, or blending that keeps lengths).
TEST(RealAssets, EveryModelBakesWithinTheFp32TargetAndTheBudget) {
  const auto files = test::realModels();
  ASSERT_GE(files.size(), 5u); // the Blender exports at least
  const std::map<std::string, std::string> textureMisses = {{"Dragon_Evolved.gltf", "Punch"}};
  for (const auto &f : files) {
    SCOPED_TRACE(f);
    Reporter r;
    r.quiet = true;
    Character c = importGltf(f, {}, r);
    AnimBakeResult res = bakeAnimation(c, textureBake(), r);
    pack::Reader reader(pack::packBytes(res.pack), f);
    EXPECT_NO_THROW(pack::loadAnimationPack(reader));
    const auto miss = textureMisses.find(std::filesystem::path(f).filename().string());
    EXPECT_EQ(res.budget.met, miss == textureMisses.end()) << res.budget.precision;
    if (miss != textureMisses.end()) {
      const AnimBakeResult chosen = bakeAnimation(c, AnimBakeOptions{}, r);
      EXPECT_EQ(chosen.stored, "tracks") << chosen.storeReason;
      for (const auto &clip : chosen.tracks) {
        EXPECT_TRUE(clip.met) << clip.clip;
        EXPECT_LE(clip.maxAnyTimeMm(), 1.0) << clip.clip;
      }
    }
    for (const auto &clip : res.accuracy[res.baked].clips) {
      const bool known = miss != textureMisses.end() && miss->second == clip.clip;
      EXPECT_LE(clip.maxAnyTime() * res.mmPerUnit, known ? 1.2 : 1.0) << clip.clip;
    }
    for (size_t k = 0; miss != textureMisses.end() && k < res.pack.clips.size(); ++k) {
      if (res.pack.clips[k].name == miss->second) {
        EXPECT_EQ(res.pack.clips[k].fps, float(kRateLadder.back()));
      }
    }
    for (const auto &clip : res.accuracy[0].clips) // float, at the budget's rates
      EXPECT_LE(clip.maxAtFrames, 1e-5 * res.diagonal) << clip.clip;
  }
}

} // namespace

namespace {
TEST(Preview, DrawsTheSkinnedCharacterInsideTheFrame) {
  AnimBakeResult r = bake(humanoid());
  auto rgb = renderPreview(r.pack, 0, 7, 128);
  size_t covered = 0, border = 0;
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x) {
      bool drawn = rgb[size_t(y * 128 + x) * 3] != 40 || rgb[size_t(y * 128 + x) * 3 + 1] != 40;
      covered += drawn;
      border += drawn && (x == 0 || y == 0 || x == 127 || y == 127);
    }
  EXPECT_GT(covered, 128u * 128 / 20); // a standing figure fills a good part of its sphere's square
  EXPECT_LT(covered, 128u * 128 / 2);
  EXPECT_EQ(border, 0u); // the bounding sphere frames the whole character
  EXPECT_EQ(rgb, renderPreview(r.pack, 0, 7, 128));
}
} // namespace

namespace {
TEST(AnimBake, AbsurdClipLengthsAreAClearError) {
  test::GltfBuilder b;
  b.skinnedQuad();
  b.animation("forever", 1, "translation", {0, 1e12f}, {0, 0.5f, 0, 0, 1, 0});
  Reporter r;
  r.quiet = true;
  Character c = importGltf(b.write(test::tempDir("anim_absurd"), "q"), {}, r);
  try {
    bakeAnimation(c, float30(), r);
    FAIL();
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("clip 'forever': "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("needs more than 65536 frames"), std::string::npos);
  }
  // The budget finds what the two keys need: two frames, exact between them.
  const AnimBakeResult fit = bakeAnimation(c, textureBake(), r);
  EXPECT_EQ(fit.pack.clips.at(0).frameCount, 2u);
  EXPECT_TRUE(fit.budget.met);
}
} // namespace

namespace {
TEST(AnimBake, SourceRatePutsFramesOnTheKeys) {
  // Linear translation keys at 0, 0.25 and 1 s: with frames on the keys, blending two frames is
  // exact; at 30 fps the key at 0.25 s falls between frames 7 and 8 and the blend cuts its corner.
  test::GltfBuilder b;
  b.skinnedQuad();
  b.animation("hop", 1, "translation", {0, 0.25f, 1}, {0, 0.5f, 0, 0, 1.5f, 0, 0, 0.5f, 0});
  Reporter r;
  r.quiet = true;
  Character c = importGltf(b.write(test::tempDir("anim_source"), "q"), {}, r);
  AnimBakeOptions source = textureBake();
  source.fps = 0;
  AnimBakeResult onKeys = bakeAnimation(c, source, r), at30 = bakeAnimation(c, float30(), r);
  EXPECT_EQ(onKeys.pack.clips[0].frameCount, 5u); // 4 fps: 0, 0.25, 0.5, 0.75, 1
  EXPECT_FLOAT_EQ(onKeys.pack.clips[0].fps, 4.0f);
  EXPECT_LE(onKeys.accuracy[0].clips[0].maxAtMidframes, 1e-6 * onKeys.diagonal);
  EXPECT_GE(at30.accuracy[0].clips[0].maxAtMidframes, 1e-3 * at30.diagonal);
  // At any time: frames on the keys stay exact between frames too; at 30 fps the mid-frame 7.5
  // is the key's time itself, where the blend of frames 7 and 8 (y = 0.5 + 28/30 and
  // 1.5 - 1/45) falls short of the key's 1.5 by 1/22.5, moving the quad's vertex weighted 0.5 to
  // the joint by 1/45 (by hand); no random time errs more, and none at the frames.
  for (const auto &pa : onKeys.accuracy) {
    if (pa.precision.name == "float" || pa.precision.name == "qts") {
      EXPECT_LE(pa.clips[0].maxAnyTime(), 1e-6 * onKeys.diagonal) << pa.precision.name;
    }
  }
  const ClipAccuracy &a = at30.accuracy[0].clips[0];
  EXPECT_GE(a.maxAtRandom, 1e-4 * at30.diagonal);
  EXPECT_GT(a.meanAtRandom, 0.0);
  EXPECT_NEAR(a.maxAtMidframes, 1 / 45.0, 1e-6);
  EXPECT_LE(a.maxAtRandom, a.maxAtMidframes);
  EXPECT_LE(a.maxAtFrames, 1e-6);
  EXPECT_EQ(a.maxAnyTime(), a.maxAtMidframes);
}

TEST(AnimBake, MillimetresAreAtA18MetreCharacter) {
  Reporter r;
  r.quiet = true;
  // The upright sample humanoid: scaled by its height.
  AnimBakeOptions one = textureBake();
  one.clip = "walk";
  AnimBakeResult h = bakeAnimation(humanoid(), one, r);
  EXPECT_FALSE(h.heightIsDiagonal);
  EXPECT_NEAR(h.mmPerUnit * restExtent(humanoid()).y, 1800.0, 1e-6);
  // A quad lying flat (no height): scaled by its diagonal.
  test::GltfBuilder b;
  b.skinnedQuad();
  b.j["nodes"][0]["rotation"] = {-0.70710678, 0, 0, 0.70710678}; // its root joint laid flat
  Character flat = importGltf(b.write(test::tempDir("anim_flat"), "q"), {}, r);
  AnimBakeResult f = bakeAnimation(flat, textureBake(), r);
  EXPECT_TRUE(f.heightIsDiagonal);
  EXPECT_NEAR(f.mmPerUnit * f.diagonal, 1800.0, 1e-6);
}
} // namespace

namespace {
// A walk exported with root motion: its last frame is its first moved along. The player cannot
// loop it (it moves no instance with a clip), so the bake says so, with the distance, instead of
// leaving a crowd that walks one cycle and stops.
TEST(AnimBake, ACycleThatTravelsIsNamedNotLooped) {
  for (bool travels : {true, false}) {
    test::GltfBuilder b;
    b.skinnedQuad();
    // Joint "a" (node 0) slides 2 units along x over a second (or out and back).
    b.animation("walk", 0, "translation", {0, 0.5f, 1},
                travels ? std::vector<float>{0, 0, 0, 1, 0, 0, 2, 0, 0}
                        : std::vector<float>{0, 0, 0, 1, 0, 0, 0, 0, 0});
    Reporter r;
    r.quiet = true;
    Character c = importGltf(b.write(test::tempDir("root_motion"), "q"), {}, r);
    const AnimBakeResult res = bakeAnimation(c, textureBake(), r);
    ASSERT_EQ(res.pack.clips.size(), 1u);
    EXPECT_EQ(res.pack.clips[0].loop, !travels);
    std::string said;
    for (const auto &w : r.warnings())
      if (w.code == "root_motion")
        said = w.message;
    if (!travels) {
      EXPECT_EQ(said, "");
      continue;
    }
    // 2 units on a quad 1 unit tall, at 1.8 m: 3.6 m in a second.
    EXPECT_NE(said.find("clip 'walk' is a cycle that travels 3.60 m (3.60 m/s"), std::string::npos)
        << said;
  }
}
} // namespace
