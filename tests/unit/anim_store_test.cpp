// What the animation bake stores (AnimBakeOptions::store): joint tracks alone make a pack
// without an animation texture that reads back, poses and reports as the texture's does; "auto"
// keeps the fewer bytes within the budget and says why.
#include <gtest/gtest.h>

#include "crowd/bake/anim_bake.h"
#include "crowd/bake/anim_report.h"
#include "crowd/formats/container.h"
#include "crowd/formats/error.h"
#include "crowd/runtime/pack_joints.h"
#include "sample_character.h"

namespace crowd {
namespace {

AnimBakeResult bakeStoring(const std::string &store) {
  Reporter r;
  r.quiet = true;
  AnimBakeOptions o;
  o.store = store;
  return bakeAnimation(test::sampleHumanoid(), o, r);
}

pack::AnimationPack readBack(const pack::AnimationPack &p) {
  return pack::loadAnimationPack(pack::Reader(pack::packBytes(p), "humanoid"));
}

// The largest distance (mm) between two packs' skinned vertices over every frame of every clip,
// and halfway to the next.
double largestPoseDifferenceMm(const pack::AnimationPack &a, const pack::AnimationPack &b,
                               double mmPerUnit) {
  double worst = 0;
  for (size_t ci = 0; ci < a.clips.size(); ++ci)
    for (uint32_t f = 0; f < a.clips[ci].frameCount; ++f)
      for (float alpha : {0.0f, 0.5f}) {
        const auto ja = runtime::sampleJoints(a, ci, f, alpha),
                   jb = runtime::sampleJoints(b, ci, f, alpha);
        for (uint32_t v = 0; v < a.mesh.vertexCount(); ++v) {
          const glm::vec3 bind(a.mesh.positions[3 * v], a.mesh.positions[3 * v + 1],
                               a.mesh.positions[3 * v + 2]);
          worst = std::max(worst, double(glm::length(runtime::skinVertex(ja, a.skin, v, bind) -
                                                     runtime::skinVertex(jb, b.skin, v, bind))) *
                                      mmPerUnit);
        }
      }
  return worst;
}

TEST(AnimStore, TracksAloneReadBackWithoutATexture) {
  const AnimBakeResult texture = bakeStoring("texture"), tracks = bakeStoring("tracks");
  EXPECT_EQ(tracks.stored, "tracks");
  const std::vector<uint8_t> bytes = pack::packBytes(tracks.pack);
  const pack::Reader reader(bytes, "humanoid");
  EXPECT_EQ(reader.find(pack::kAnimationTexture), nullptr);
  ASSERT_NE(reader.find(pack::kJointTracks), nullptr);
  const pack::AnimationPack back = pack::loadAnimationPack(reader);
  EXPECT_FALSE(back.hasTexture());
  ASSERT_TRUE(back.tracks);
  // The clip table keeps the texture's frames: morph weights and cloth loops count them.
  EXPECT_EQ(back.animation.frameCount, texture.pack.animation.frameCount);
  EXPECT_EQ(back.animation.jointCount, texture.pack.skeleton.jointCount());
  EXPECT_EQ(pack::packBytes(back), bytes);
  const double mm = largestPoseDifferenceMm(readBack(texture.pack), back, texture.mmPerUnit);
  std::printf("tracks alone against the texture: %.3f mm at most; %zu against %zu pack bytes\n", mm,
              bytes.size(), pack::packBytes(texture.pack).size());
  // Each within the 1 mm budget of the source: never more than two budgets apart.
  EXPECT_LE(mm, 2.0);
  EXPECT_GT(mm, 0.0) << "the texture and the tracks cannot pose identically";
  EXPECT_LT(bytes.size(), pack::packBytes(texture.pack).size());
}

TEST(AnimStore, AutoKeepsTheFewerBytesWithinTheBudgetAndSaysWhy) {
  const AnimBakeResult r = bakeStoring("auto");
  ASSERT_EQ(r.tracks.size(), r.pack.clips.size());
  EXPECT_EQ(r.stored, "tracks");
  EXPECT_LT(r.tracksBytes(), r.textureBytes());
  EXPECT_NE(r.storeReason.find("both meet the budget, tracks in fewer bytes"), std::string::npos)
      << r.storeReason;
  const auto report = animFigures(r);
  EXPECT_EQ(report["store"], "tracks");
  EXPECT_EQ(report["animation_bytes"].get<uint64_t>(), r.tracksBytes());
  EXPECT_TRUE(report["budget_met"].get<bool>());
  for (size_t i = 0; i < r.pack.clips.size(); ++i) { // each clip's errors are the tracks'
    EXPECT_EQ(report["clips"][i]["max_error_any_time_mm"].get<double>(),
              r.tracks[i].maxAnyTimeMm());
    EXPECT_EQ(report["clips"][i]["animation_bytes"].get<uint64_t>(), r.tracks[i].bytes);
  }
}

// A budget no texture rate reaches but the tracks (on the source keys) do: auto stores them.
TEST(AnimStore, AutoStoresWhatMeetsTheBudget) {
  Reporter rep;
  rep.quiet = true;
  AnimBakeOptions o;
  o.store = "auto";
  o.fps = 10; // forced: the texture blends matrices 100 ms apart and misses
  o.precision = "float";
  const AnimBakeResult r = bakeAnimation(test::sampleHumanoid(), o, rep);
  EXPECT_FALSE(r.budget.met);
  EXPECT_EQ(r.stored, "tracks");
  EXPECT_NE(r.storeReason.find("only tracks meets the budget"), std::string::npos) << r.storeReason;
}

TEST(AnimStore, APackWithNeitherTextureNorTracksIsAClearError) {
  pack::AnimationPack p = readBack(bakeStoring("tracks").pack);
  p.tracks.reset();
  try {
    pack::packBytes(p);
    FAIL() << "a pack without animation was written";
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("neither an animation texture nor joint tracks"),
              std::string::npos)
        << e.what();
  }
  // And read: a pack whose TRAK chunk was dropped names the ANIM chunk it then needs.
  const pack::Reader full(pack::packBytes(bakeStoring("tracks").pack), "humanoid");
  pack::Writer w;
  for (const pack::ChunkEntry &c : full.chunks())
    if (c.type != pack::kJointTracks) {
      const auto payload = full.payload(c);
      w.add(c.type, c.version, {payload.begin(), payload.end()});
    }
  try {
    pack::loadAnimationPack(pack::Reader(w.bytes(), "dropped"));
    FAIL() << "a pack without animation was read";
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("ANIM"), std::string::npos) << e.what();
  }
}

// The choice itself, on figures: the fewer bytes among the encodings within the budget, else
// the one erring less; an encoding just over the budget never counts as meeting it.
TEST(AnimStore, TheChoiceTakesTheFewerBytesOnlyWithinTheBudget) {
  EXPECT_EQ(chooseStore(1.0, {0.8, 1000}, {0.9, 400}).stored, "tracks");
  EXPECT_EQ(chooseStore(1.0, {0.8, 300}, {0.9, 400}).stored, "texture");
  const StoreChoice over = chooseStore(1.0, {0.8, 1000}, {1.5, 400});
  EXPECT_EQ(over.stored, "texture");
  EXPECT_EQ(over.reason.rfind("only texture meets the budget", 0), 0u) << over.reason;
  EXPECT_EQ(chooseStore(1.0, {1.01, 100}, {0.99, 400}).stored, "tracks");
  const StoreChoice neither = chooseStore(1.0, {3.0, 100}, {1.2, 400});
  EXPECT_EQ(neither.stored, "tracks");
  EXPECT_EQ(neither.reason.rfind("neither meets the budget, tracks errs less", 0), 0u)
      << neither.reason;
  EXPECT_EQ(chooseStore(1.0, {1.0, 1000}, {1.0, 400}).stored, "tracks"); // at the budget: met
}

} // namespace
} // namespace crowd
