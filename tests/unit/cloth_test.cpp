// Cloth caches (PC2, MDD) and pass 1 of the cloth-loop search, on caches made here whose loops
// are known: a swing with twice the body's period (only even cycle counts close), a transient
// that dies out (late loops close better), and noise (nothing closes).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>

#include <gtest/gtest.h>

#include "crowd/bake/cloth_input.h"
#include "crowd/bake/cloth_loop.h"
#include "crowd/bake/edge_match.h"
#include "crowd/bake/loop_search.h"
#include "crowd/support/point_cache.h"
#include "crowd/formats/error.h"
#include "crowd/samples/cloth_caches.h"
#include "gltf_writer.h"
#include "sample_character.h"
#include <map>

using namespace crowd;

namespace {

using Frames = std::vector<std::vector<glm::vec3>>;

// A skirt-like ring of `vertices` points swinging with period `period` frames, plus a
// transient exp(-f / decay) (decay 0: none).
Frames swinging(uint32_t frames, uint32_t vertices, double period, double decay = 0.0) {
  Frames out(frames, std::vector<glm::vec3>(vertices));
  for (uint32_t f = 0; f < frames; ++f)
    for (uint32_t v = 0; v < vertices; ++v) {
      const double a = 6.2831853 * v / vertices, phase = 6.2831853 * f / period;
      const double swing =
          0.1 * std::sin(phase + a) + (decay > 0 ? 0.2 * std::exp(-double(f) / decay) : 0);
      out[f][v] =
          glm::vec3(0.3 * std::cos(a) + swing, 0.8 - 0.02 * std::cos(phase), 0.3 * std::sin(a));
    }
  return out;
}

std::string writeCache(const std::string &name, const std::vector<uint8_t> &bytes) {
  const std::string path = test::tempDir("cloth") + "/" + name;
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char *>(bytes.data()), std::streamsize(bytes.size()));
  return path;
}

std::string errorOf(const std::function<void()> &fn) {
  try {
    fn();
  } catch (const Error &e) {
    return e.what();
  }
  return "no error";
}

ClothFrames inMemory(const Frames &frames) {
  return [&frames](uint32_t f, uint32_t first, uint32_t count, std::vector<glm::vec3> &out) {
    out.assign(frames[f].begin() + first, frames[f].begin() + first + count);
  };
}

LoopSearch search(const Frames &frames, double cycle, int threads = 0, uint32_t maxCycles = 0) {
  LoopSearchOptions o;
  o.cycleFrames = cycle;
  o.threads = threads;
  o.maxCycles = maxCycles;
  return searchLoops(uint32_t(frames.size()), uint32_t(frames[0].size()), inMemory(frames), o);
}

} // namespace

TEST(PointCache, Pc2AndMddRoundTripFrameByFrame) {
  const Frames frames = swinging(7, 600, 5.0);
  for (auto format : {PointCacheFormat::Pc2, PointCacheFormat::Mdd}) {
    const bool mdd = format == PointCacheFormat::Mdd;
    PointCacheReader r(writeCache(mdd ? "a.mdd" : "a.pc2", encodePointCache(format, frames, 24.0)),
                       {});
    EXPECT_EQ(r.info().frameCount, 7u);
    EXPECT_EQ(r.info().vertexCount, 600u);
    EXPECT_NEAR(r.info().fps, mdd ? 24.0 : 0.0, 1e-3); // PC2 stores no frame rate
    std::vector<glm::vec3> out;
    r.read(5, 550, 50, out); // a range of one frame, read on its own
    for (uint32_t v = 0; v < 50; ++v)
      EXPECT_EQ(out[v], frames[5][550 + v]);
    r.readFrame(0, out);
    EXPECT_EQ(out, frames[0]);
  }
}

TEST(PointCache, ASmallMddShorterThanAPc2HeaderReads) {
  const Frames one = {{glm::vec3(1, 2, 3)}}; // 24 bytes in all
  PointCacheReader r(writeCache("one.mdd", encodePointCache(PointCacheFormat::Mdd, one, 30)), {});
  std::vector<glm::vec3> out;
  r.readFrame(0, out);
  EXPECT_EQ(out, one[0]);
}

TEST(PointCache, DamagedFilesAreClearErrors) {
  const Frames frames = swinging(4, 10, 5.0);
  auto pc2 = encodePointCache(PointCacheFormat::Pc2, frames, 30.0);
  auto mdd = encodePointCache(PointCacheFormat::Mdd, frames, 30.0);
  const auto open = [](const std::string &name, const std::vector<uint8_t> &bytes) {
    return errorOf([&] { PointCacheReader(writeCache(name, bytes), {}); });
  };
  auto longer = pc2; // bytes past the frames the header counts: not the file it describes
  longer.resize(longer.size() + 12);
  EXPECT_NE(open("long.pc2", longer).find("header says 4 frames of 10 vertices"), std::string::npos)
      << open("long.pc2", longer);
  auto cut = pc2;
  cut.resize(cut.size() - 7);
  EXPECT_NE(open("cut.pc2", cut).find("(truncated?)"), std::string::npos) << open("cut.pc2", cut);
  auto lying = pc2;
  lying[28] = 200; // frame count 200, file holds 4
  EXPECT_NE(open("lie.pc2", lying).find("header says 200 frames of 10 vertices"),
            std::string::npos);
  lying = pc2;
  lying[16] = 0; // zero vertices
  EXPECT_NE(open("zero.pc2", lying).find("0 vertices"), std::string::npos);
  auto mddCut = mdd;
  mddCut.resize(100);
  EXPECT_NE(open("cut.mdd", mddCut).find("MDD header says 4 frames"), std::string::npos);
  auto skewed = mdd;
  skewed[8 + 3 * 4] ^= 0x40; // frame 3's time
  EXPECT_NE(open("skew.mdd", skewed).find("uniform step"), std::string::npos)
      << open("skew.mdd", skewed);
  EXPECT_NE(open("text.pc2", {'h', 'i'}).find("no POINTCACHE2 header"), std::string::npos);

  Frames bad = frames;
  bad[2][7].y = std::nanf("");
  PointCacheReader r(writeCache("nan.pc2", encodePointCache(PointCacheFormat::Pc2, bad, 30)), {});
  std::vector<glm::vec3> out;
  EXPECT_NO_THROW(r.readFrame(1, out));
  EXPECT_NE(errorOf([&] { r.readFrame(2, out); }).find("frame 2, vertex 7: position is not finite"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { r.read(4, 0, 1, out); }).find("outside the cache"), std::string::npos);
}

TEST(LoopSearch, ASwingOfTwoCyclesClosesOnlyOnEvenCycles) {
  // The cloth swings once every two body cycles of 16 frames: odd loops jump by the full swing.
  const Frames frames = swinging(16 * 12, 300, 32.0);
  const LoopSearch s = search(frames, 16.0);
  ASSERT_EQ(s.candidates.size(), 5u);
  for (const auto &c : s.candidates) {
    EXPECT_EQ(c.cycles % 2, 0u) << c.start << " " << c.cycles;
    EXPECT_EQ(c.length, 16 * c.cycles);
    EXPECT_LT(c.positionJump, 1e-5);
    EXPECT_LT(c.velocityJump, 1e-5);
  }
  EXPECT_GT(s.meanMotion, 0.001);
  // An odd loop in the chart is far worse than the chosen one.
  const size_t oddRow = 0; // 1 cycle
  EXPECT_GT(s.distances[oddRow * frames.size() + 40], 1e-3);
  // --max-cycles 4: only loops of 2 and 4 cycles remain, and the chart stops at 4.
  const LoopSearch capped = search(frames, 16.0, 0, 4);
  EXPECT_EQ(capped.maxCycles, 4u);
  EXPECT_EQ(capped.distances.size(), 4 * frames.size());
  ASSERT_FALSE(capped.candidates.empty());
  for (const auto &c : capped.candidates) {
    EXPECT_LE(c.cycles, 4u);
    EXPECT_EQ(c.cycles % 2, 0u);
  }
}

TEST(LoopSearch, ATransientThatDiesOutIsLeftBehind) {
  const Frames frames = swinging(20 * 15, 200, 20.0, 40.0);
  const LoopSearch s = search(frames, 20.0);
  const auto &best = s.candidates.front();
  // The loop's seam is where the transient has faded most: the loop ends near the cache's end.
  EXPECT_GT(best.start + best.length, frames.size() - 20);
  EXPECT_LT(best.positionJump, s.meanMotion);
  for (size_t i = 1; i < s.candidates.size(); ++i)
    EXPECT_LE(best.distance, s.candidates[i].distance);
}

TEST(LoopSearch, NoiseNeverClosesAndThreadsDoNotChangeTheResult) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-0.05f, 0.05f);
  Frames frames(24 * 6, std::vector<glm::vec3>(700));
  for (auto &frame : frames)
    for (auto &p : frame)
      p = {u(rng), 1.0f + u(rng), u(rng)};
  const LoopSearch one = search(frames, 24.0, 1), two = search(frames, 24.0, 2);
  ASSERT_EQ(one.candidates.size(), two.candidates.size());
  for (size_t i = 0; i < one.candidates.size(); ++i) {
    EXPECT_EQ(one.candidates[i].start, two.candidates[i].start);
    EXPECT_EQ(one.candidates[i].distance, two.candidates[i].distance);
  }
  // The best seam still jumps about as far as any frame moves: the verdict's evidence.
  EXPECT_GT(one.candidates.front().positionJump, 0.8 * one.meanMotion);
  EXPECT_GT(one.candidates.front().velocityJump, 0.5 * one.meanVelocityChange);
}

TEST(LoopSearch, ShortCachesAndBadOptionsAreErrors) {
  const Frames frames = swinging(30, 10, 16.0);
  EXPECT_NE(errorOf([&] { search(frames, 16.0); }).find("needs at least 2 cycles"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { search(frames, 0.5); }).find("cycle:"), std::string::npos);
  LoopSearchOptions o;
  o.cycleFrames = 8;
  o.candidates = 0;
  EXPECT_NE(errorOf([&] { o.validate(); }).find("candidates"), std::string::npos);
  o.candidates = 5;
  o.minCycles = 3;
  o.maxCycles = 2;
  EXPECT_NE(errorOf([&] { o.validate(); }).find("max-cycles: 2 is under min-cycles 3"),
            std::string::npos);
}

TEST(LoopSearch, StreamsFromAPointCacheAFewVerticesAtATime) {
  const Frames frames = swinging(16 * 6, 1100, 32.0); // three blocks of vertices
  PointCacheReader reader(
      writeCache("stream.pc2", encodePointCache(PointCacheFormat::Pc2, frames, 30)), {});
  uint32_t widest = 0;
  const ClothFrames fromFile = [&](uint32_t f, uint32_t first, uint32_t count, auto &out) {
    if (count < 1100)
      widest = std::max(widest, count);
    reader.read(f, first, count, out);
  };
  LoopSearchOptions o;
  o.cycleFrames = 16;
  const LoopSearch streamed = searchLoops(96, 1100, fromFile, o);
  const LoopSearch held = search(frames, 16.0);
  EXPECT_EQ(widest, 512u); // blocks of 512 vertices, not whole frames, during the search
  ASSERT_EQ(streamed.candidates.size(), held.candidates.size());
  EXPECT_EQ(streamed.candidates[0].start, held.candidates[0].start);
  EXPECT_EQ(streamed.candidates[0].distance, held.candidates[0].distance);
}

// The sample caches (samples/src/cloth_sim.cpp) through both passes and the verdict, 12 cycles
// of each here (the samples simulate 40; loop_search_bench measures those): the loose skirts
// close within the target (seam jumps under the mean per-frame motion and velocity
// change) and the verdict's stricter limit, without repeating exactly; the stiff one settles;
// noise is rejected, with its figures.
TEST(SampleCloth, LooseSkirtsCloseStiffOnesSettleNoiseNever) {
  const auto choose = [](const Frames &frames, double cycle) {
    ClothLoopOptions o;
    o.search.cycleFrames = cycle;
    const LoopChoice loop = chooseLoop(uint32_t(frames.size()), uint32_t(frames[0].size()),
                                       inMemory(frames), samples::dressIndices(), o);
    const LoopCandidate &best = loop.candidates.front().seam;
    EXPECT_EQ(best.length, std::lround(best.cycles * cycle));
    for (size_t i = 1; i < loop.candidates.size(); ++i) // pass 2's order
      EXPECT_LE(loop.candidates[0].edgeDistance, loop.candidates[i].edgeDistance);
    return loop;
  };
  std::map<std::string, LoopChoice> r;
  for (const auto &sample : samples::cacheSamples()) {
    samples::ClothSettings settings = sample.settings;
    settings.cycles = std::min(settings.cycles, 12u);
    const Frames frames = samples::simulateDress(settings);
    EXPECT_EQ(frames[0].size(), samples::dressVertexCount());
    r[sample.file] = choose(frames, settings.fps * (settings.clip == "run" ? 0.7 : 1.0));
    std::printf("%s, %u cycles: %s\n", sample.file.c_str(), settings.cycles,
                r[sample.file].verdict.c_str());
  }
  for (const char *loose : {"skirt_walk.pc2", "skirt_run.pc2"}) {
    EXPECT_TRUE(r[loose].acceptable) << loose;
    EXPECT_LE(r[loose].velocityRatio, 1.0) << loose; // the targets
    EXPECT_LE(r[loose].positionRatio, 1.0) << loose;
    EXPECT_LT(r[loose].bestToMedian, 0.5) << loose;
    EXPECT_GT(r[loose].positionRatio, 2 * r["skirt_stiff.pc2"].positionRatio)
        << loose << ": repeats exactly";
  }
  EXPECT_LT(r["skirt_stiff.pc2"].positionRatio, 0.15);
  // Noise: a clear verdict, never a silent bad loop.
  const Frames noise = samples::noiseCache(30 * 4, samples::dressVertexCount());
  const LoopChoice never = choose(noise, 30.0);
  EXPECT_FALSE(never.acceptable);
  EXPECT_GT(never.positionRatio, 0.8);
  EXPECT_GT(never.bestToMedian, 0.8);
  EXPECT_GE(never.blendFrames, 2u);
  EXPECT_NE(never.verdict.find("no acceptable loop"), std::string::npos) << never.verdict;
}

// Pass 2 on the sample dress: the same pose is 0 pixels from itself; a pose moved up is farther
// the farther it moves; two poses half a stride apart differ.
TEST(EdgeMatch, DistanceGrowsWithTheShiftAndIsZeroForTheSamePose) {
  const Frames frames = samples::simulateDress({"walk", 1, 30.0, 16, 1e-7f, 2e-4f, 0.3});
  const std::vector<uint32_t> &indices = samples::dressIndices();
  EdgeMatchOptions o;
  for (double d : edgeDistances(frames[10], frames[10], indices, o))
    EXPECT_EQ(d, 0.0);
  double previous = 0.0;
  for (float shift : {0.005f, 0.02f, 0.06f}) { // a radius of ~0.5 m spans 80 pixels
    std::vector<glm::vec3> moved = frames[10];
    for (auto &p : moved)
      p.y += shift;
    const auto d = edgeDistances(frames[10], moved, indices, o);
    ASSERT_EQ(d.size(), 5u);
    double sum = 0.0;
    for (double x : d)
      sum += x;
    std::printf("shift %.3f m: edge distance %.2f px per view\n", shift, sum / 5);
    EXPECT_GT(sum, previous);
    previous = sum;
  }
  // 0.06 m is about 9 pixels; edges running up and down (the skirt's sides) do not move, so the
  // mean over every edge pixel is a fraction of that.
  EXPECT_GT(previous / 5, 1.0);
  EXPECT_GT(edgeDistances(frames[0], frames[15], indices, o)[0], 0.5); // half a stride apart
  o.cannyHigh = 10;
  EXPECT_NE(errorOf([&] { edgeDistances(frames[0], frames[1], indices, o); }).find("canny"),
            std::string::npos);
}

// The sample dress's cache against the imported outfit: it fits garment "dress" (count and
// order), a shuffled or shortened cache does not, PC2 needs --fps, and the root-frame reader
// feeds the search (the sample clips stay in place: the root frame is the cache's).
TEST(ClothInput, TheSampleCacheFitsItsGarmentAndAShuffledOneDoesNot) {
  const auto outfits = test::sampleOutfits();
  const Character &dress = outfits[0].character, &body = test::sampleHumanoid();
  const AnimationClip &walk = body.clips[0];
  ASSERT_EQ(walk.name, "walk");
  const std::vector<uint32_t> ids = garmentVertices(dress, "dress");
  ASSERT_EQ(ids.size(), samples::dressVertexCount());
  EXPECT_NE(errorOf([&] { garmentVertices(dress, "cape"); }).find("no garment named 'cape'"),
            std::string::npos);
  Frames frames = samples::simulateDress({"walk", 3, 30.0, 16, 1e-7f, 2e-4f, 0.3});
  PointCacheReader cache(writeCache("fit.pc2", encodePointCache(PointCacheFormat::Pc2, frames, 30)),
                         {});
  ClothCacheOptions o;
  EXPECT_NE(errorOf([&] { cacheFps(cache, o); }).find("give --fps"), std::string::npos);
  o.fps = 30;
  EXPECT_EQ(cacheFps(cache, o), 30.0);
  EXPECT_NO_THROW(checkGarment(cache, dress, ids, walk, o));

  Frames shuffled = frames;
  for (auto &f : shuffled)
    std::reverse(f.begin(), f.end());
  PointCacheReader wrong(
      writeCache("shuffled.mdd", encodePointCache(PointCacheFormat::Mdd, shuffled, 30)), {});
  EXPECT_EQ(cacheFps(wrong, {}), 30.0);
  EXPECT_NE(errorOf([&] { checkGarment(wrong, dress, ids, walk, o); }).find("vertex order"),
            std::string::npos);
  Frames shorter = frames;
  for (auto &f : shorter)
    f.pop_back();
  PointCacheReader fewer(
      writeCache("short.pc2", encodePointCache(PointCacheFormat::Pc2, shorter, 30)), {});
  EXPECT_NE(errorOf([&] {
              checkGarment(fewer, dress, ids, walk, o);
            }).find("1045 vertices, but the garment has 1046"),
            std::string::npos);

  LoopSearchOptions so;
  so.cycleFrames = 30.0 * (walk.end - walk.start);
  const LoopSearch viaRoot = searchLoops(uint32_t(frames.size()), uint32_t(ids.size()),
                                         rootFrames(cache, body, walk, 30.0), so);
  const LoopSearch direct = search(frames, so.cycleFrames);
  EXPECT_EQ(viaRoot.candidates.front().start, direct.candidates.front().start);
  EXPECT_NEAR(viaRoot.candidates.front().distance, direct.candidates.front().distance, 1e-9);
}

// Pass 1 is exactly its definition: on a small random cache, every (start, cycles) cell is the
// binomially filtered (1 2 1) / 4 mean of |p(s + L) - p(s)|^2 + |v(s + L) - v(s)|^2 per vertex.
TEST(LoopSearch, EveryCellIsTheFilteredKovarDistance) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Frames frames(14, std::vector<glm::vec3>(4));
  for (auto &frame : frames)
    for (auto &p : frame)
      p = {u(rng), u(rng), u(rng)};
  LoopSearchOptions o;
  o.cycleFrames = 3;
  o.window = 1;
  o.candidates = 3;
  const LoopSearch s = searchLoops(14, 4, inMemory(frames), o);
  const auto raw = [&](size_t a, size_t b) {
    double sum = 0.0;
    for (size_t v = 0; v < 4; ++v) {
      const glm::dvec3 d0 = glm::dvec3(frames[b][v]) - glm::dvec3(frames[a][v]);
      const glm::dvec3 d1 = glm::dvec3(frames[b + 1][v]) - glm::dvec3(frames[a + 1][v]);
      sum += glm::dot(d0, d0) + glm::dot(d1 - d0, d1 - d0);
    }
    return sum / 4.0;
  };
  size_t checked = 0;
  for (uint32_t c = s.minCycles; c <= s.maxCycles; ++c)
    for (uint32_t start = 0; start < 14; ++start) {
      const double d = s.distances[(c - s.minCycles) * 14 + start];
      const uint32_t len = 3 * c;
      const bool valid = start >= 1 && start + len + 2 < 14;
      EXPECT_EQ(std::isnan(d), !valid) << c << " " << start;
      if (!valid)
        continue;
      const double expected = (raw(start - 1, start - 1 + len) + 2 * raw(start, start + len) +
                               raw(start + 1, start + 1 + len)) /
                              4.0;
      EXPECT_NEAR(d, expected, 1e-5 * expected) << c << " " << start;
      ++checked;
    }
  EXPECT_GT(checked, 10u);
  EXPECT_EQ(s.candidates.front().distance,
            *std::min_element(s.distances.begin(), s.distances.end(), [](double a, double b) {
              return !std::isnan(a) && (std::isnan(b) || a < b);
            }));
}
