// The cloth-loop bake end to end on the sample dress: a loose skirt's loop is a hard cut that
// replays its cache frames within the quantisation step; noise is cross-faded and pushed out
// of the body; the CLTH chunk round-trips and its damage is a clear error; manifests name loops.
#include <fstream>

#include <gtest/gtest.h>

#include "crowd/bake/cloth_bake.h"
#include "crowd/bake/evaluate.h"
#include "crowd/bake/job.h"
#include "crowd/bake/manifest.h"
#include "crowd/bake/outfit_bake.h"
#include "crowd/formats/character_pack.h"
#include "crowd/formats/container.h"
#include "crowd/formats/error.h"
#include "crowd/samples/cloth_caches.h"
#include "gltf_writer.h"
#include "sample_character.h"

using namespace crowd;

namespace {

using Frames = std::vector<std::vector<glm::vec3>>;

std::string writeCache(const std::string &name, const Frames &frames, double fps = 30) {
  const auto bytes = encodePointCache(PointCacheFormat::Pc2, frames, fps);
  const std::string path = test::tempDir("cloth_bake") + "/" + name;
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char *>(bytes.data()), std::streamsize(bytes.size()));
  return path;
}

ClothBakeResult bake(const std::string &cache, ClothBakeOptions o, Reporter &rep) {
  if (o.cache.fps == 0)
    o.cache.fps = 30;
  rep.quiet = true;
  return bakeClothLoop(test::sampleHumanoid(), test::sampleOutfits()[0].character, "dress", "dress",
                       "walk", cache, {}, o, rep);
}

// The cache in the body's root frame, as the bake reads it.
Frames rootFramesOf(const std::string &cache) {
  PointCacheReader reader(cache, {});
  const Character &body = test::sampleHumanoid();
  const ClothFrames frames = rootFrames(reader, body, body.clips[0], 30.0);
  Frames out(reader.info().frameCount);
  for (uint32_t f = 0; f < out.size(); ++f)
    frames(f, 0, reader.info().vertexCount, out[f]);
  return out;
}

double largest(const std::array<float, 3> &a) { return std::max({a[0], a[1], a[2]}); }

} // namespace

TEST(ClothBake, ALooseSkirtIsAHardCutThatReplaysItsCacheFrames) {
  samples::ClothSettings s = samples::cacheSamples()[0].settings; // skirt_walk
  ASSERT_EQ(s.clip, "walk");
  s.cycles = 8;
  const std::string path = writeCache("walk.pc2", samples::simulateDress(s));
  Reporter rep;
  const ClothBakeResult r = bake(path, {}, rep);
  const pack::ClothLoop &c = r.chunk;
  EXPECT_TRUE(r.loop.acceptable) << r.loop.verdict;
  EXPECT_FALSE(r.rate.mismatch) << r.rate.residual << " against " << r.rate.bestResidual;
  EXPECT_EQ(c.blendFrames, 0u);
  EXPECT_EQ(r.pushedVertices, 0u);
  EXPECT_EQ(c.vertexCount(), samples::dressVertexCount());
  const AnimationClip &walk = test::sampleHumanoid().clips[0];
  EXPECT_NEAR(c.frameCount(), c.cycles * (walk.end - walk.start) * 30.0, 0.5);
  // Every stored frame is the cache's frame (start + f) within half a quantisation step per axis.
  const Frames root = rootFramesOf(path);
  const double halfStep = 0.5 * largest(c.step) * std::sqrt(3.0) * 1.0001;
  double worst = 0;
  for (uint32_t f = 0; f < c.frameCount(); ++f)
    for (uint32_t v = 0; v < c.vertexCount(); ++v) {
      const auto q = c.position(f, v);
      worst = std::max(
          worst, double(glm::length(glm::vec3(q[0], q[1], q[2]) - root[c.cacheStart + f][v])));
    }
  EXPECT_LE(worst, halfStep);
  EXPECT_NEAR(r.quantMaxMm, worst * r.mmPerUnit, 1e-3);
  EXPECT_LT(r.quantMaxMm, 0.022); // 16 bits over a ~1 m box: 0.0109 mm measured
  // The chunk round-trips.
  const pack::ClothLoop back = pack::decodeClothLoop(pack::encode(c), "test");
  EXPECT_EQ(back.positions, c.positions);
  EXPECT_EQ(back.sources.expand(), c.sources.expand());
  EXPECT_EQ(back.cycles, c.cycles);
}

// A cache simulated at 24 fps under a clip baked at 30: the loop is whole clip cycles of the
// cache's own frames. Read at the wrong rate (30), a "cycle" is 1.25 true cycles: 4 of them are
// 5 true ones, a seam that closes as well, so the verdict cannot tell; the frame-rate fit can:
// the skirt's waistband follows the body at 24 fps, not at 30.
TEST(ClothBake, ACacheAtAnotherFrameRateLoopsInItsOwnFrames) {
  samples::ClothSettings s = samples::cacheSamples()[0].settings; // skirt_walk
  s.cycles = 8;
  s.fps = 24;
  const std::string path = writeCache("walk24.pc2", samples::simulateDress(s), 24);
  ClothBakeOptions o;
  o.cache.fps = 24;
  Reporter rep;
  const ClothBakeResult r = bake(path, o, rep);
  EXPECT_TRUE(r.loop.acceptable) << r.loop.verdict;
  EXPECT_EQ(r.chunk.fps, 24.0f);
  const AnimationClip &walk = test::sampleHumanoid().clips[0];
  EXPECT_NEAR(r.chunk.frameCount(), r.chunk.cycles * (walk.end - walk.start) * 24.0, 0.5);
  EXPECT_FALSE(r.rate.mismatch) << r.rate.residual << " against " << r.rate.bestResidual;
  EXPECT_TRUE(rep.warnings().empty());
  o.cache.fps = 30; // the wrong rate: a cycle is 25% too long
  Reporter wrong;
  const ClothBakeResult w = bake(path, o, wrong);
  std::printf("24 fps cache read at 24: seam %.2fx / %.2fx the mean motion / velocity change; "
              "read at 30: %.2fx / %.2fx (%s)\n",
              r.loop.positionRatio, r.loop.velocityRatio, w.loop.positionRatio,
              w.loop.velocityRatio, w.loop.acceptable ? "accepted" : "rejected");
  EXPECT_EQ(w.chunk.fps, 30.0f);
  EXPECT_EQ(w.chunk.cycles % 4, 0u); // only multiples of 4 false cycles close
  EXPECT_TRUE(w.rate.mismatch);
  EXPECT_EQ(w.rate.bestRate, 24.0);
  EXPECT_LT(w.rate.bestResidual, 0.5 * w.rate.residual);
  ASSERT_FALSE(wrong.warnings().empty());
  EXPECT_EQ(wrong.warnings()[0].code, "cloth_fps_mismatch");
  std::printf("waistband off the skinned skirt: %.2f mm at 24 fps, %.2f mm read at 30\n",
              w.rate.bestResidual * w.mmPerUnit, w.rate.residual * w.mmPerUnit);
}

TEST(ClothBake, NoiseIsCrossFadedAndWhatTheBlendPushedIntoTheBodyComesOut) {
  const std::string path =
      writeCache("noise.pc2", samples::noiseCache(30 * 4, samples::dressVertexCount()));
  Reporter rep;
  const ClothBakeResult r = bake(path, {}, rep);
  const pack::ClothLoop &c = r.chunk;
  ASSERT_FALSE(r.loop.acceptable);
  EXPECT_FALSE(r.rate.mismatch) << "noise follows no body: every rate fits alike";
  EXPECT_EQ(c.blendFrames, std::min(r.loop.blendFrames, c.cacheStart));
  ASSERT_GT(c.blendFrames, 1u);
  // The last frame now leads into the first: it is the blend of its own frame and the frame
  // just before the start, weighted K / (K + 1) towards the latter.
  const Frames root = rootFramesOf(path);
  const uint32_t last = c.frameCount() - 1, k = c.blendFrames;
  const float w = float(k) / float(k + 1);
  size_t checked = 0;
  for (uint32_t v = 0; v < c.vertexCount(); v += 7) {
    const glm::vec3 expected = glm::mix(root[c.cacheStart + last][v], root[c.cacheStart - 1][v], w);
    const auto q = c.position(last, v);
    const float d = glm::length(glm::vec3(q[0], q[1], q[2]) - expected);
    if (d < 1e-3f) // not pushed
      ++checked;
  }
  EXPECT_GT(checked, c.vertexCount() / 7 / 2);
  // Noise jitters vertices through the legs: some blended ones land inside and are pushed out,
  // by at most the noise's reach plus the margin.
  EXPECT_GT(r.pushedVertices, 0u);
  EXPECT_GT(r.pushMaxMm, 0.0);
  EXPECT_LT(r.pushMaxMm, 200.0);

  ClothBakeOptions hard;
  hard.blend = 0; // a hard cut always: said, not silent
  Reporter rep2;
  const ClothBakeResult cut = bake(path, hard, rep2);
  EXPECT_EQ(cut.chunk.blendFrames, 0u);
  ASSERT_FALSE(rep2.warnings().empty());
  EXPECT_EQ(rep2.warnings()[0].code, "cloth_hard_cut");
}

TEST(ClothChunk, DamageAndMismatchesAreClearErrors) {
  pack::ClothLoop c;
  c.garment = "dress";
  c.clip = "walk";
  c.fps = 30;
  c.cycles = 1;
  c.outfit = "dress";
  c.sources = pack::SourceMap::of({{0, 0, 0, 0, 2}, {0, 0, 0, 0, 5}});
  c.positions.assign(2 * 3 * 4, 7); // 4 frames
  const auto bytes = pack::encode(c);
  EXPECT_EQ(pack::decodeClothLoop(bytes, "t").frameCount(), 4u);
  for (size_t cut : {size_t(0), size_t(10), bytes.size() - 1})
    EXPECT_THROW(pack::decodeClothLoop({bytes.data(), cut}, "t"), Error) << cut;
  auto bad = c;
  bad.sources = pack::SourceMap::of({{0, 0, 0, 0, 2}, {}}); // a vertex without a source
  EXPECT_THROW(pack::decodeClothLoop(pack::encode(bad), "t"), Error);
  bad = c; // one ordinal over runs of a billion vertices: refused before anything expands them
  bad.sources.runs = {{{0, 0, 0, 0, 0}, 1u << 30}};
  bad.sources.ordinals = {0, 1};
  EXPECT_THROW(pack::decodeClothLoop(pack::encode(bad), "t"), Error);
  bad = c;
  bad.positions.pop_back(); // not whole frames
  EXPECT_THROW(pack::decodeClothLoop(pack::encode(bad), "t"), Error);
  bad = c;
  bad.blendFrames = 4;
  EXPECT_THROW(pack::decodeClothLoop(pack::encode(bad), "t"), Error);
  bad = c;
  bad.fps = NAN;
  EXPECT_THROW(pack::decodeClothLoop(pack::encode(bad), "t"), Error);

  // In a character pack, the loop's clip, outfit and vertices must be the pack's: here the
  // humanoid with an outfit "dress" whose file holds mesh vertices 10 and 11 as 2 and 5.
  pack::CharacterPack p;
  p.body = test::sampleHumanoidLodPack();
  const auto subMeshes = uint32_t(p.body.mesh.subMeshes.size());
  pack::Outfits table;
  table.bodySubMeshes = subMeshes;
  table.colours.assign(4 * subMeshes, 1.0f);
  table.textured.assign(subMeshes, 0);
  table.outfits.push_back({"dress", std::vector(subMeshes, pack::Coverage::Visible), {}});
  for (uint32_t s = 0; s < subMeshes; ++s)
    table.outfits[0].subMeshes.push_back(s);
  p.body.outfits = table;
  auto sources = p.body.sources->expand();
  sources[10] = {1, 0, 0, 0, 2};
  sources[11] = {1, 0, 0, 0, 5};
  p.body.sources = pack::SourceMap::of(sources);
  const auto of = pack::clothVertexOf(p.body, c, "t");
  EXPECT_EQ(of[10], 0);
  EXPECT_EQ(of[11], 1);
  EXPECT_EQ(std::count(of.begin(), of.end(), -1), std::ptrdiff_t(of.size() - 2));
  c.clip = "swim";
  p.cloths = {c};
  try {
    pack::loadCharacterPack(pack::Reader(pack::packBytes(p), "p"));
    FAIL() << "no error";
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("'swim' is not a clip of the pack"), std::string::npos)
        << e.what();
  }
  c.clip = "walk";
  p.cloths = {c};
  EXPECT_EQ(pack::loadCharacterPack(pack::Reader(pack::packBytes(p), "p")).cloths.size(), 1u);
  auto run = c;
  run.clip = "run";
  p.cloths = {c, run}; // two loops of one garment
  EXPECT_EQ(pack::loadCharacterPack(pack::Reader(pack::packBytes(p), "p")).cloths.size(), 2u);
  p.cloths = {c, c};
  EXPECT_THROW(pack::loadCharacterPack(pack::Reader(pack::packBytes(p), "p")), Error);
  c.sources = pack::SourceMap::of({{0, 0, 0, 0, 2}, {0, 0, 0, 0, 6}}); // 6: not in the mesh
  p.cloths = {c};
  try {
    pack::loadCharacterPack(pack::Reader(pack::packBytes(p), "p"));
    FAIL() << "no error";
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("1 of the loop's 2 vertices are not in the mesh"),
              std::string::npos)
        << e.what();
  }
}

// Visibility tests a looped garment where its loop has it: a loop that carries the dress far
// above the head leaves the body about as bare as no outfit does, though the skinned dress
// hides the torso. (Coarse settings: this is about which poses are tested, not about rays.)
// A two-frame loop of the sample dress over the walk, every vertex at `origin` in the root frame.
pack::ClothLoop dressLoop(const OutfitInput &dress, std::array<float, 3> origin) {
  const auto garment = garmentVertices(dress.character, "dress");
  pack::ClothLoop loop;
  loop.outfit = loop.garment = "dress";
  loop.clip = "walk";
  loop.fps = 30;
  loop.cycles = 1;
  std::vector<pack::VertexSource> sources;
  for (uint32_t v : garment)
    sources.push_back(dress.character.mesh.sources[v]);
  loop.sources = pack::SourceMap::of(sources);
  loop.origin = origin;
  loop.step = {1e-3f, 1e-3f, 1e-3f};
  loop.positions.assign(2 * 3 * garment.size(), 0); // 2 frames
  return loop;
}

TEST(ClothVisibility, ALoopThatSwingsTheGarmentAwayUncoversTheBody) {
  Reporter rep;
  rep.quiet = true;
  const Character &body = test::sampleHumanoid();
  OutfitInput dress = test::sampleOutfits()[0];
  const Character joined = dressCharacter(body, dress, "material", rep);
  std::vector<size_t> garmentParts;
  for (size_t p = body.mesh.parts.size(); p < joined.mesh.parts.size(); ++p)
    garmentParts.push_back(p);
  const auto garment = garmentVertices(dress.character, "dress");
  dress.loops = {dressLoop(dress, {0.0f, 50.0f, 0.0f})}; // 50 m up in the root frame
  const auto loops = placeLoops(joined, {dress}, {uint32_t(body.mesh.vertexCount())});
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].vertices.size(), garment.size());
  VisibilityOptions o;
  o.rays = 6;
  o.points = 1;
  o.frameStep = 1000; // each clip's first and last frames
  o.loopFrames = 1;
  const auto bodyTriangles = uint32_t(body.mesh.indices.size() / 3);
  auto count = [](const std::vector<uint8_t> &h) { return std::count(h.begin(), h.end(), 1); };
  const auto bare = count(hiddenBodyFaces(joined, bodyTriangles, {}, o));
  const auto dressed = count(hiddenBodyFaces(joined, bodyTriangles, garmentParts, o));
  const auto looped = count(hiddenBodyFaces(joined, bodyTriangles, garmentParts, o, loops));
  std::printf("hidden body faces: bare %td, dressed %td, dressed with a loop swinging away %td\n",
              bare, dressed, looped);
  EXPECT_GT(dressed, bare + 100);
  // About bare: the bare count is over every clip frame, the loop's frame is one pose of them.
  EXPECT_LE(looped, bare + bare / 10);
  // The loop's frame is posed: the garment's vertices 50 m above the top joint.
  const auto poses = outfitPoses(joined, o.fps, o.frameStep, loops, o.loopFrames);
  ASSERT_TRUE(poses.back().loop);
  const auto p = posed(joined, poses.back());
  EXPECT_GT(p[loops[0].vertices[0]].y, 40.0);
}

// With LOD the merged mesh is reordered (and flat shading welded): the placed loops follow, so
// the hole check poses each loop vertex where it now is (before, they kept the pre-LOD numbers).
TEST(ClothVisibility, LoopVerticesFollowTheLodOrder) {
  Reporter rep;
  rep.quiet = true;
  OutfitInput dress = test::sampleOutfits()[0];
  dress.loops = {dressLoop(dress, {0.0f, 0.0f, 0.0f})};
  const std::vector<pack::VertexSource> sources = dress.loops[0].sources.expand();
  OutfitOptions o;
  o.visibility.rays = 6;
  o.visibility.points = 1;
  o.visibility.frameStep = 1000;
  o.visibility.loopFrames = 1;
  o.lod = LodOptions{};
  o.lod->poses = 2;
  const OutfitBakeResult r = bakeOutfits(test::sampleHumanoid(), {dress}, o, rep);
  ASSERT_EQ(r.loops.size(), 1u);
  ASSERT_EQ(r.loops[0].vertices.size(), sources.size());
  for (size_t k = 0; k < sources.size(); ++k) {
    ASSERT_LT(r.loops[0].vertices[k], r.merged.mesh.vertexCount());
    pack::VertexSource s = r.merged.mesh.sources[r.loops[0].vertices[k]];
    s.file = sources[k].file; // the merged mesh numbers the outfit's file
    EXPECT_EQ(s, sources[k]) << "loop vertex " << k;
  }
}

TEST(ClothManifest, LoopsNameTheirOutfitClipAndCache) {
  const std::string dir = test::tempDir("cloth_manifest");
  for (const char *f : {"b.glb", "d.glb", "c.pc2"})
    std::ofstream(dir + "/" + f) << "x";
  const std::string head = R"({"name": "n", "body": "b.glb", "outfits": {"dress": "d.glb"}, )";
  const CharacterManifest m = parseManifest(
      head + R"("cloth": [{"outfit": "dress", "garment": "g", "clip": "walk", "cache": "c.pc2",
               "fps": 25, "blend": 4, "max_cycles": 6}]})",
      dir + "/m.json");
  ASSERT_EQ(m.cloth.size(), 1u);
  EXPECT_EQ(m.cloth[0].cache, dir + "/c.pc2");
  EXPECT_EQ(m.cloth[0].options.cache.fps, 25.0);
  EXPECT_EQ(m.cloth[0].options.blend, 4);
  EXPECT_EQ(m.cloth[0].options.loop.search.maxCycles, 6u);
  EXPECT_EQ(m.canonical()["cloth"][0]["max_cycles"], 6);
  EXPECT_EQ(m.canonical()["cloth"][0]["garment"], "g");
  // The plan: the loop's job first, the mesh job (whose visibility poses the loop) reading it,
  // then the link reading the mesh first and the loop after.
  const auto jobs = planCharacter(std::make_shared<CharacterManifest>(m), 10);
  ASSERT_EQ(jobs.size(), 3u);
  EXPECT_EQ(jobs[0].kind, "cloth");
  EXPECT_EQ(jobs[1].kind, "mesh");
  EXPECT_EQ(jobs[1].deps, std::vector<size_t>{10});
  EXPECT_FALSE(jobs[1].settings.contains("cloth")); // it comes as a part, keyed by its job
  EXPECT_EQ(jobs[1].settings["visibility"]["loop_frames"], 32);
  EXPECT_EQ(jobs[2].kind, "link");
  EXPECT_EQ(jobs[2].deps, (std::vector<size_t>{11, 10}));
  auto error = [&](const std::string &cloth) {
    try {
      parseManifest(head + R"("cloth": )" + cloth + "}", dir + "/m.json");
    } catch (const Error &e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error(R"([{"outfit": "cape", "garment": "g", "clip": "walk", "cache": "c.pc2"}])")
                .find("'cape' is not one of the character's outfits"),
            std::string::npos);
  EXPECT_NE(error(R"([{"outfit": "dress", "garment": "g", "clip": "walk"}])")
                .find("a cloth loop needs \"cache\""),
            std::string::npos);
  const std::string one =
      R"({"outfit": "dress", "garment": "g", "clip": "walk", "cache": "c.pc2"})";
  EXPECT_NE(error("[" + one + ", " + one + "]").find("a second loop"), std::string::npos);
  EXPECT_NE(error(R"([{"outfit": "dress", "garment": "g", "clip": "walk", "cache": "c.pc2",
                       "blend": 2.5}])")
                .find("expected a whole number of frames"),
            std::string::npos);
  EXPECT_NE(
      error(R"([{"outfit": "dress", "garment": "g", "clip": "walk", "cache": "/etc/c.pc2"}])"),
      "no error");
  // Unset, the cap is not in the loop's key: the keys of loops baked before it stay valid.
  EXPECT_FALSE(parseManifest(head + R"("cloth": [)" + one + "]}", dir + "/m.json")
                   .cloth[0]
                   .canonical()
                   .contains("max_cycles"));
}
