// What the animation bake stores (AnimBakeOptions::store): joint tracks alone make a pack
// without an animation texture that reads back, poses and reports as the texture's does; "auto"
// keeps the fewer bytes within the budget and says why.
#include <cmath>
#include <cstdio>
#include <tuple>

#include <gtest/gtest.h>

#include "crowd/bake/anim_bake.h"
#include "crowd/bake/anim_report.h"
#include "crowd/bake/import.h"
#include "crowd/bake/manifest.h"
#include "crowd/formats/container.h"
#include "crowd/formats/error.h"
#include "crowd/runtime/pack_joints.h"
#include "gltf_writer.h"
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

// The largest distance (mm) between two packs' skinned vertices at the times of every frame of
// every clip of `a`, and halfway to the next (each pack's clip table places them).
double largestPoseDifferenceMm(const pack::AnimationPack &a, const pack::AnimationPack &b,
                               double mmPerUnit) {
  double worst = 0;
  for (size_t ci = 0; ci < a.clips.size(); ++ci)
    for (uint32_t f = 0; f < a.clips[ci].frameCount; ++f)
      for (float alpha : {0.0f, 0.5f}) {
        const float seconds = std::min((float(f) + alpha) / a.clips[ci].fps,
                                       float(a.clips[ci].frameCount - 1) / a.clips[ci].fps);
        const runtime::ClipTime atB = runtime::clipTimeAt(b.clips[ci], seconds);
        const auto ja = runtime::sampleJoints(a, ci, f, alpha),
                   jb = runtime::sampleJoints(b, ci, atB.frame, atB.alpha);
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
  // No texture searched: the clip table samples each clip on its keys (its source rate), over
  // the same durations, and counts its frames for the morph weights.
  const Character c = test::sampleHumanoid();
  ASSERT_EQ(back.clips.size(), texture.pack.clips.size());
  uint32_t frames = 0;
  for (size_t ci = 0; ci < back.clips.size(); ++ci) {
    const pack::Clip &k = back.clips[ci], &t = texture.pack.clips[ci];
    EXPECT_NEAR(k.fps, sourceRate(c.clips.at(ci)), 1e-3) << k.name;
    EXPECT_NEAR((k.frameCount - 1) / k.fps, (t.frameCount - 1) / t.fps, 1e-5f) << k.name;
    EXPECT_EQ(k.loop, t.loop) << k.name;
    frames += k.frameCount;
  }
  EXPECT_EQ(back.animation.frameCount, frames);
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

// Tracks within the budget in fewer bytes than any texture could take: no texture is searched,
// and the pack is the one --store tracks writes.
TEST(AnimStore, AutoKeepsTracksFewerThanAnyTextureWithoutSearchingOne) {
  const AnimBakeResult r = bakeStoring("auto"), texture = bakeStoring("texture");
  ASSERT_EQ(r.tracks.size(), r.pack.clips.size());
  EXPECT_EQ(r.stored, "tracks");
  EXPECT_TRUE(r.accuracy.empty()); // not measured
  EXPECT_NE(r.storeReason.find("fewer than any texture takes"), std::string::npos) << r.storeReason;
  BudgetSearch all;
  for (const auto &p : precisions())
    all.tried.push_back(&p);
  all.matrixJoints = texture.budget.matrixJoints;
  const Character c = test::sampleHumanoid();
  std::vector<const AnimationClip *> clips;
  for (const auto &clip : c.clips)
    clips.push_back(&clip);
  const uint64_t fewest = fewestTextureBytes(c, clips, all);
  EXPECT_LE(r.tracksBytes(), fewest);
  EXPECT_LE(fewest, texture.textureBytes()); // a floor of what the search found
  EXPECT_EQ(pack::packBytes(r.pack), pack::packBytes(bakeStoring("tracks").pack));
  const auto report = animFigures(r);
  EXPECT_FALSE(report.contains("precision"));
  EXPECT_FALSE(report.contains("precisions"));
  EXPECT_EQ(report["store"], "tracks");
  EXPECT_EQ(report["animation_bytes"].get<uint64_t>(), r.tracksBytes());
  EXPECT_TRUE(report["budget_met"].get<bool>());
  for (size_t i = 0; i < r.pack.clips.size(); ++i) { // each clip's errors are the tracks'
    EXPECT_EQ(report["clips"][i]["max_error_any_time_mm"].get<double>(),
              r.tracks[i].maxAnyTimeMm());
    EXPECT_EQ(report["clips"][i]["animation_bytes"].get<uint64_t>(), r.tracks[i].bytes);
  }
}

// An option that shapes the texture is never silently dropped: under auto a forced precision
// or rate stores the texture (measured, the report naming it and why); under tracks a
// precision is an error naming the conflict, and a rate sets the tracks' clip table.
TEST(AnimStore, AutoWithAForcedTextureStoresIt) {
  for (const auto &[fps, precision, named] :
       {std::tuple{10.0, std::string("float"), std::string("precision float")},
        std::tuple{10.0, std::string("auto"), std::string("fps 10")},
        std::tuple{AnimBakeOptions::kFpsSource, std::string("auto"), std::string("fps source")},
        std::tuple{AnimBakeOptions::kFpsFromBudget, std::string("half"),
                   std::string("precision half")}}) {
    Reporter rep;
    rep.quiet = true;
    AnimBakeOptions o;
    o.fps = fps;
    o.precision = precision;
    const AnimBakeResult r = bakeAnimation(test::sampleHumanoid(), o, rep);
    EXPECT_EQ(r.stored, "texture") << named;
    EXPECT_EQ(r.storeReason.rfind(named + " shapes the texture", 0), 0u) << r.storeReason;
    EXPECT_FALSE(r.pack.tracks) << named;
    ASSERT_FALSE(r.accuracy.empty()) << named;
    if (precision != "auto") {
      EXPECT_EQ(r.accuracy[r.baked].precision.name, precision);
    }
    if (fps > 0) {
      for (const auto &clip : r.pack.clips)
        EXPECT_NEAR(clip.fps, float(fps), 1e-4f) << clip.name;
    }
    const auto report = animFigures(r);
    EXPECT_EQ(report["store"], "texture");
    EXPECT_EQ(report["store_reason"], r.storeReason);
    EXPECT_EQ(report["precision"], r.accuracy[r.baked].precision.name);
  }
}

TEST(AnimStore, TracksWithAPrecisionIsAnErrorAndARateSetsTheClipTable) {
  Reporter rep;
  rep.quiet = true;
  AnimBakeOptions o;
  o.store = "tracks";
  o.precision = "half";
  try {
    bakeAnimation(test::sampleHumanoid(), o, rep);
    ADD_FAILURE() << "a precision under store tracks baked";
  } catch (const Error &e) {
    EXPECT_EQ(std::string(e.what()).rfind("precision: half shapes the texture, which store "
                                          "tracks leaves out",
                                          0),
              0u)
        << e.what();
  }
  o.precision = "auto";
  o.fps = 10;
  const AnimBakeResult r = bakeAnimation(test::sampleHumanoid(), o, rep);
  EXPECT_EQ(r.stored, "tracks");
  EXPECT_TRUE(r.accuracy.empty()); // no texture searched
  for (const auto &clip : r.pack.clips)
    EXPECT_NEAR(clip.fps, 10.0f, 1e-4f) << clip.name;
  for (const auto &t : r.tracks)
    EXPECT_TRUE(t.met) << t.clip;
}

// Where auto measured the texture and kept the tracks, the report names no precision at the top
// (the pack holds none) and lists the measured ones under "precisions".
TEST(AnimStore, AReportNamesOnlyWhatThePackHolds) {
  Reporter rep;
  rep.quiet = true;
  AnimBakeOptions o;
  o.store = "both";
  AnimBakeResult r = bakeAnimation(test::sampleHumanoid(), o, rep);
  ASSERT_FALSE(r.accuracy.empty());
  EXPECT_TRUE(animFigures(r).contains("precision"));
  r.stored = "tracks"; // as auto leaves a result whose texture lost
  EXPECT_FALSE(animFigures(r).contains("precision"));
  EXPECT_TRUE(animFigures(r).contains("precisions"));
}

// A two-joint quad whose second joint turns about z from rest to (0, 0, z, w) over `seconds`, on
// two keys (one clip, "turn"), imported from test::tempDir(folder). With `floatRest`, both joints'
// rest values are no half floats: the skeleton takes 10 floats a joint in the tracks.
Character turningQuad(const std::string &folder, float seconds, float z, float w, Reporter &rep,
                      bool floatRest = false) {
  test::GltfBuilder g;
  g.skinnedQuad();
  if (floatRest)
    for (size_t n : {0, 1}) {
      g.j["nodes"][n]["rotation"] = {0, 0.0099998f, 0, 0.99995f};
      g.j["nodes"][n]["scale"] = {1.001f, 1.001f, 1.001f};
      g.j["nodes"][n]["translation"] = {0.001f, n ? 0.5f : 0.001f, 0};
    }
  g.animation("turn", 1, "rotation", {0, seconds}, {0, 0, 0, 1, 0, 0, z, w});
  return importGltf(g.write(test::tempDir(folder), "turn"), {}, rep);
}

// Tracks that may take more than a texture (a two-joint quad turning over one second, its rest
// values floats: the tracks' skeleton alone outweighs two texture frames): the texture is
// searched, measured and compared.
TEST(AnimStore, AutoSearchesTheTextureWhereTracksMayTakeMore) {
  Reporter rep;
  rep.quiet = true;
  const Character c = turningQuad("store_fallback", 1, 0.38268343f, 0.92387953f, rep, true);
  const AnimBakeResult r = bakeAnimation(c, {}, rep);
  BudgetSearch all;
  for (const auto &p : precisions())
    all.tried.push_back(&p);
  all.matrixJoints = r.budget.matrixJoints;
  ASSERT_FALSE(r.accuracy.empty()) << r.storeReason; // searched and measured
  EXPECT_EQ(r.stored, "texture") << r.storeReason;
  EXPECT_NE(r.storeReason.find("both meet the budget, texture in fewer bytes"), std::string::npos)
      << r.storeReason;
  // Searched because the tracks (skeleton and clip, as the reason gives them) took more than
  // the floor; the floor is below what the search found.
  const size_t at = r.storeReason.find("; tracks ");
  ASSERT_NE(at, std::string::npos) << r.storeReason;
  const uint64_t tracks = std::stoull(r.storeReason.substr(at + 9));
  const uint64_t fewest = fewestTextureBytes(c, {&c.clips.at(0)}, all);
  EXPECT_GT(tracks, fewest);
  EXPECT_LE(fewest, r.textureBytes());
  EXPECT_FALSE(r.budget.clips.at(0).tried.empty());
  EXPECT_NE(r.storeReason.find("texture " + std::to_string(r.textureBytes()) + " bytes"),
            std::string::npos)
      << r.storeReason;
  EXPECT_TRUE(animFigures(r).contains("precisions"));
}

// Tracks above the texture's floor but below any texture that meets the budget (a quarter turn
// over ten seconds on two keys: two frames blend it badly, ten a second outweigh the tracks):
// the search stops at the tracks' bytes and no texture is measured.
TEST(AnimStore, AutoStopsTheSearchAtTheTracksBytes) {
  Reporter rep;
  rep.quiet = true;
  const Character c = turningQuad("store_capped", 10, 0.70710678f, 0.70710678f, rep);
  const AnimBakeResult r = bakeAnimation(c, {}, rep);
  EXPECT_EQ(r.stored, "tracks");
  EXPECT_TRUE(r.accuracy.empty()); // not measured
  EXPECT_NE(r.storeReason.find("no texture tried in fewer bytes meets it"), std::string::npos)
      << r.storeReason;
  ASSERT_EQ(r.budget.clips.size(), 1u);
  const ClipBudget &b = r.budget.clips[0];
  EXPECT_TRUE(b.capped);
  ASSERT_FALSE(b.tried.empty());
  for (const auto &o : b.tried) { // the lowest rate alone: 10 fps, next, takes 101 frames
    EXPECT_FALSE(o.meets) << o.fps << " " << o.precision;
    EXPECT_EQ(o.fps, b.tried[0].fps) << o.precision;
  }
  EXPECT_GT(101 * 2 * pack::texelsPerJoint(pack::JointEncoding::QuatTransScale) *
                pack::bytesPerTexel(pack::TexelFormat::RGBA16F),
            r.tracksBytes());
  EXPECT_NEAR(r.pack.clips.at(0).fps, 0.1f, 1e-6f); // the table stays on the keys
  EXPECT_TRUE(animFigures(r)["clips"][0].contains("options_tried"));
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

// One check of the error budget: the CLI's options, the tracks' options and a manifest refuse
// the same budgets with the same words.
TEST(AnimOptions, TheBudgetIsCheckedInOnePlace) {
  const std::string manifest = std::string(CROWD_SOURCE_DIR) + "/tests/data/blender/t.json";
  for (double mm : {0.0, -1.0, 2e6, double(NAN), double(INFINITY)}) {
    const std::string problem = errorBudgetProblem(mm);
    ASSERT_FALSE(problem.empty()) << mm;
    AnimBakeOptions anim;
    anim.errorBudgetMm = mm;
    try {
      anim.validate();
      ADD_FAILURE() << mm;
    } catch (const Error &e) {
      EXPECT_EQ(std::string(e.what()), "error-budget: " + problem);
    }
    TrackCompressionOptions tracks;
    tracks.errorBudgetMm = mm;
    try {
      tracks.validate();
      ADD_FAILURE() << mm;
    } catch (const Error &e) {
      EXPECT_EQ(std::string(e.what()), "errorBudgetMm: " + problem);
    }
    if (!std::isfinite(mm))
      continue; // JSON has no such number
    char text[64];
    std::snprintf(text, sizeof text, "%.17g", mm);
    const std::string json =
        std::string(R"({"name": "t", "body": "trooper_cm.glb", "anim": {"error_budget_mm": )") +
        text + "}}";
    try {
      parseManifest(json, manifest);
      ADD_FAILURE() << mm;
    } catch (const Error &e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("/anim/error_budget_mm: " + problem), std::string::npos) << what;
    }
  }
  for (double mm : {1e-6, 1.0, 1e6})
    EXPECT_EQ(errorBudgetProblem(mm), "") << mm;
}

} // namespace
} // namespace crowd
