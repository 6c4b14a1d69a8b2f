#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "crowd/bake/import.h"
#include "crowd/bake/impostor_bake.h"
#include "crowd/formats/error.h"
#include "crowd/formats/limits.h"
#include "crowd/runtime/impostor_runtime.h"
#include "gltf_writer.h"
#include "sample_character.h"

using namespace crowd;

namespace {

const Character &humanoid() { return test::sampleHumanoid(); }

ImpostorOptions small() {
  ImpostorOptions o;
  o.clip = "walk";
  o.frames = 3;
  o.azimuths = 8;
  o.elevations = 2;
  o.texels = 48;
  return o;
}

TEST(Impostor, SameBytesAtAnyThreadCount) {
  Reporter r;
  auto o = small();
  o.threads = 1;
  auto one = pack::packBytes(pack::ImpostorPack{{}, bakeImpostor(humanoid(), o, r).impostor});
  o.threads = 3;
  auto three = pack::packBytes(pack::ImpostorPack{{}, bakeImpostor(humanoid(), o, r).impostor});
  EXPECT_EQ(one, three);
}

TEST(Impostor, ViewsAreCroppedPackedWithoutOverlapAndHoldRegions) {
  Reporter r;
  ImpostorBakeResult res = bakeImpostor(humanoid(), small(), r);
  const auto &m = res.impostor;
  ASSERT_EQ(m.views.size(), 3u * 16);
  EXPECT_GT(res.occupancy, 0.5);
  EXPECT_LT(res.bytesPerFrame, res.naiveBytesPerFrame);
  for (uint32_t f = 0; f < m.frames; ++f) {
    std::vector<int> owner(size_t(m.atlasWidth) * m.atlasHeight, -1);
    for (uint32_t v = 0; v < 16; ++v) {
      const auto &view = m.views[f * 16 + v];
      ASSERT_GT(view.width, 0) << "the character is in every view";
      size_t filled = 0;
      for (uint32_t y = view.y; y < uint32_t(view.y) + view.height; ++y)
        for (uint32_t x = view.x; x < uint32_t(view.x) + view.width; ++x) {
          size_t t = size_t(y) * m.atlasWidth + x;
          ASSERT_EQ(owner[t], -1) << "views overlap in frame " << f;
          owner[t] = int(v);
          const uint8_t *texel = &m.atlases[(size_t(f) * m.atlasWidth * m.atlasHeight + t) * 4];
          EXPECT_LE(texel[3], humanoid().mesh.parts.size());
          filled += texel[3] > 0;
          // Dilated: empty texels of a crop hold a neighbour's normal (never black), region 0.
          ASSERT_GT(int(texel[0]) + texel[1] + texel[2], 0) << "undilated texel in frame " << f;
        }
      // Cropped to the silhouette: every crop row and column is touched, so it is well filled.
      EXPECT_GT(filled, size_t(view.width) * view.height / 5);
      // The pivot is the sphere centre, which the character's silhouette surrounds.
      EXPECT_GT(view.pivotX, 0);
      EXPECT_LT(view.pivotX, view.width);
    }
  }
  // The UV map shares the layout and carries the same region ids.
  ASSERT_EQ(m.uvAtlases.size(), m.atlases.size());
  for (size_t t = 0; t < m.atlases.size(); t += 4)
    ASSERT_EQ(m.uvAtlases[t + 2], m.atlases[t + 3]);
  pack::Reader reader(pack::packBytes(pack::ImpostorPack{{}, m}), "mem");
  EXPECT_EQ(pack::loadImpostorPack(reader).impostor.views.size(), m.views.size());
}

TEST(Impostor, OneFrameClipsRestPosesAndMemoryGuard) {
  Reporter r;
  r.quiet = true;
  auto o = small();
  o.frames = 1;
  EXPECT_EQ(bakeImpostor(humanoid(), o, r).impostor.frames, 1u);

  test::GltfBuilder b;
  b.skinnedQuad(); // no animation: the rest pose, with a warning
  Character quad = importGltf(b.write(test::tempDir("impostor_quad"), "q"), {}, r);
  ImpostorOptions q = small();
  q.clip = "";
  auto res = bakeImpostor(quad, q, r);
  EXPECT_EQ(res.impostor.clip, "rest");
  std::set<std::string> codes;
  for (const auto &w : r.warnings())
    codes.insert(w.code);
  EXPECT_TRUE(codes.count("no_animation"));
  EXPECT_TRUE(codes.count("no_uvs")) << "the quad has no UVs: no UV map";
  EXPECT_TRUE(res.impostor.uvAtlases.empty());

  EXPECT_TRUE(codes.count("empty_views")) << "the flat quad seen edge-on from the horizon";

  auto huge = small();
  huge.frames = 64;
  huge.azimuths = 64;
  huge.elevations = 16;
  huge.texels = 4096;
  try {
    bakeImpostor(humanoid(), huge, r);
    FAIL();
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("lower --frames, --views or --texels"), std::string::npos);
  }
}

} // namespace

namespace {
TEST(Impostor, TexelsFromTheSwitchDistanceCoverAPixelThereAndClampPast512) {
  Reporter r;
  r.quiet = true;
  auto o = small();
  o.frames = 1;
  o.azimuths = 2;
  o.elevations = 1;
  o.switchDistance = 12;
  const auto far = bakeImpostor(humanoid(), o, r).impostor;
  // At the switch, a pixel spans 2 d tan(fov / 2) / H units and a texel 2 r / texels: the
  // fewest texels (a multiple of 4) for which a texel is at most a pixel.
  const double radius = far.sphere[3];
  const double pixel = 2 * o.switchDistance * std::tan(o.fovDegrees * M_PI / 360) / o.screenHeight;
  EXPECT_EQ(far.texels % 4, 0u);
  EXPECT_LE(2 * radius / far.texels, pixel * (1 + 1e-9));
  EXPECT_GT(2 * radius / (far.texels - 4), pixel);
  EXPECT_TRUE(r.warnings().empty());

  o.switchDistance = 0.5; // nearer than 512 texels can serve
  const auto near = bakeImpostor(humanoid(), o, r).impostor;
  EXPECT_EQ(near.texels, limits::kAutoImpostorTexels);
  ASSERT_EQ(r.warnings().size(), 1u);
  EXPECT_EQ(r.warnings()[0].code, "texels_clamped");
}

TEST(Impostor, MirroringIsMeasuredNotAssumed) {
  Reporter r;
  auto o = small();
  o.frames = 4; // even: frame f + 2 is half a walk cycle later
  auto res = bakeImpostor(humanoid(), o, r);
  EXPECT_GT(res.mirrorIouMean, 0.95) << "the sample walk is left-right symmetric";
  EXPECT_LE(res.mirrorIouMin, res.mirrorIouMean);
  o.frames = 3;
  EXPECT_EQ(bakeImpostor(humanoid(), o, r).mirrorIouMean, -1) << "odd frame counts: not measured";
}
} // namespace

namespace {
TEST(Impostor, BestPlaneSitsOnTheVisibleSurface) {
  Reporter r;
  auto o = small();
  o.elevations = 4;
  auto m = bakeImpostor(humanoid(), o, r).impostor;
  double radius = m.sphere[3];
  std::vector<double> byElevation(4, 0.0);
  for (uint32_t e = 0; e < 4; ++e)
    for (uint32_t a = 0; a < 8; ++a) {
      double offset = m.views[m.viewIndex(0, e, a)].planeOffset;
      // The visible surface is the near side: in front of the centre, inside the sphere.
      EXPECT_GT(offset, 0.0) << e << " " << a;
      EXPECT_LT(offset, 0.6 * radius) << e << " " << a;
      byElevation[e] += offset / 8;
    }
  // Seen from higher up, the visible surface is the top of the body, further above the centre.
  EXPECT_LT(byElevation[0], byElevation[3]);
}
} // namespace

namespace {
TEST(Impostor, AccuracyIsExactAtTheViewsAndImprovesWithMoreViews) {
  Reporter r;
  auto o = small();
  auto coarse = bakeImpostor(humanoid(), o, r).impostor;
  ImpostorAccuracy a = measureImpostor(humanoid(), coarse, 1);
  // At a stored view the impostor is that view: only 8-bit normal quantisation is left.
  EXPECT_GE(a.atViews.iouMin, 0.999);
  EXPECT_LT(a.atViews.normalMeanDeg, 1.0);
  EXPECT_LT(a.betweenViews.iouMean, a.atViews.iouMean);
  // Per elevation row: the rows' means average to the whole mean.
  for (const auto *f : {&a.atViews, &a.betweenViews}) {
    ASSERT_EQ(f->iouMeanByElevation.size(), o.elevations);
    double sum = 0;
    for (double row : f->iouMeanByElevation)
      sum += row;
    EXPECT_NEAR(sum / o.elevations, f->iouMean, 1e-9);
  }
  o.azimuths = 32;
  o.elevations = 8;
  ImpostorAccuracy fine = measureImpostor(humanoid(), bakeImpostor(humanoid(), o, r).impostor, 1);
  EXPECT_GT(fine.betweenViews.iouMean, a.betweenViews.iouMean);
  EXPECT_LT(fine.betweenViews.normalMeanDeg, a.betweenViews.normalMeanDeg);
}
} // namespace

namespace {
TEST(Impostor, MirroredPacksStoreHalfTheAzimuthsAndStillMatch) {
  Reporter r;
  auto o = small();
  o.frames = 4;
  o.mirror = true;
  auto mirrored = bakeImpostor(humanoid(), o, r);
  const auto &m = mirrored.impostor;
  EXPECT_TRUE(m.mirrored);
  EXPECT_EQ(m.views.size(), 4u * 2 * 5); // azimuths 0..4 of 8
  auto [index, flip] = m.lookup(0, 1, 6);
  EXPECT_TRUE(flip);
  EXPECT_EQ(index, m.viewIndex(2, 1, 2)); // azimuth 8 - 6, two frames (half the clip) later
  ImpostorAccuracy a = measureImpostor(humanoid(), m, 1);
  EXPECT_GE(a.atViews.iouMean, 0.99); // the mirrored views stand in for the real ones
  EXPECT_LT(a.atViews.normalMeanDeg, 2.0);
  pack::Reader reader(pack::packBytes(pack::ImpostorPack{{}, m}), "mem");
  EXPECT_TRUE(pack::loadImpostorPack(reader).impostor.mirrored);
  o.frames = 3;
  EXPECT_THROW(bakeImpostor(humanoid(), o, r), Error);
}
} // namespace

namespace {
// What the player's impostor shader does, on the CPU: the view it picks is the stored view that
// the bake rendered from the nearest direction, half a clip later and flipped when mirrored.
TEST(ImpostorRuntime, ChoosesTheNearestStoredViewAndFrame) {
  Reporter r;
  auto o = small();
  o.frames = 4;
  o.mirror = true;
  const auto m = bakeImpostor(humanoid(), o, r).impostor;
  const double pi = 3.14159265358979323846, step = m.frameStep;
  auto dir = [&](double azDeg, double elDeg) {
    double a = azDeg * pi / 180, e = elDeg * pi / 180;
    return glm::vec3(std::cos(e) * std::sin(a), std::sin(e), std::cos(e) * std::cos(a));
  };
  auto c = runtime::chooseImpostorView(m, dir(44, 10), 1.1 * step, true);
  EXPECT_EQ(c.azimuth, 1u);   // 45 degrees apart: 44 is nearest to 45
  EXPECT_EQ(c.elevation, 0u); // rows at 22.5 and 67.5
  EXPECT_EQ(c.frame, 1u);
  EXPECT_FALSE(c.flip);
  EXPECT_EQ(c.view, m.viewIndex(1, 0, 1));
  c = runtime::chooseImpostorView(m, dir(-90, 80), 4.9 * step, true); // wraps to frame 1
  EXPECT_EQ(c.azimuth, 6u);
  EXPECT_EQ(c.elevation, 1u);
  EXPECT_TRUE(c.flip);
  EXPECT_EQ(c.frame, 3u); // frame 1, mirrored: half the clip later
  EXPECT_EQ(c.view, m.viewIndex(3, 1, 2));
  c = runtime::chooseImpostorView(m, dir(0, 10), 9 * step, false); // past the end: clamped
  EXPECT_EQ(c.frame, 3u);
  // The 1:1 distance: a texel (2 r / texels) covers a pixel.
  double d = runtime::oneToOneDistance(m, pi / 2, 480);
  EXPECT_NEAR(2.0 * d * std::tan(pi / 4) / 480, 2.0 * m.sphere[3] / m.texels, 1e-9);
}

TEST(ImpostorRuntime, MipLevelsNeverAverageRegionIds) {
  pack::Impostor m;
  m.frames = 1;
  m.atlasWidth = 4;
  m.atlasHeight = 2;
  // Block 1: regions 1, 3, 3, empty -> 3 (the mode), never 2. Block 2: one texel covered -> empty.
  const uint8_t a[8] = {1, 3, 0, 0, 3, 0, 0, 9};
  for (uint8_t region : a) {
    m.atlases.insert(m.atlases.end(), {uint8_t(region * 20), 0, 0, region});
    m.uvAtlases.insert(m.uvAtlases.end(), {uint16_t(region * 1000), 7, region, 0});
  }
  auto mips = runtime::impostorMips(m, 0, 8);
  ASSERT_EQ(mips.size(), 3u); // 4x2, 2x1, 1x1
  EXPECT_EQ(mips[1].width, 2u);
  EXPECT_EQ(mips[1].normals[3], 3);
  EXPECT_EQ(mips[1].normals[0], 60); // the normal of a region-3 texel, not a blend
  EXPECT_EQ(mips[1].uvs[0], 3000);
  EXPECT_EQ(mips[1].normals[7], 0); // a lone covered texel does not survive
  EXPECT_EQ(mips[2].normals[3], 3); // one covered texel of two: half
}
} // namespace

namespace {
TEST(Impostor, DegenerateMeshesFailClearlyAndExtraRegionsAreClamped) {
  Reporter r;
  r.quiet = true;
  Character flat = humanoid();
  for (auto &p : flat.mesh.positions)
    p = glm::vec3(0.1f, 0.2f, 0.3f); // every triangle collapses to a point
  try {
    bakeImpostor(flat, small(), r);
    FAIL() << "a degenerate mesh baked";
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("degenerate"), std::string::npos) << e.what();
  }

  // 300 sub-meshes: ids above 254 do not fit the 8-bit region channel.
  Character many = humanoid();
  const uint32_t triangles = uint32_t(many.mesh.indices.size() / 3);
  many.mesh.parts.clear();
  for (uint32_t k = 0; k < 300; ++k) {
    uint32_t first = triangles * k / 300, last = triangles * (k + 1) / 300;
    many.mesh.parts.push_back({"part" + std::to_string(k), first * 3, (last - first) * 3});
  }
  auto res = bakeImpostor(many, small(), r);
  bool warned = false;
  for (const auto &w : r.warnings())
    warned |= w.code == "too_many_regions";
  EXPECT_TRUE(warned);
  uint8_t highest = 0;
  for (size_t t = 3; t < res.impostor.atlases.size(); t += 4)
    highest = std::max(highest, res.impostor.atlases[t]);
  EXPECT_EQ(highest, 255); // clamped, not wrapped around to low ids
}
} // namespace
