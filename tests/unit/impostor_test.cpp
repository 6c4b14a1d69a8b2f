#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <set>

#include <gtest/gtest.h>

#include "crowd/bake/bake_figures.h"
#include "crowd/bake/import.h"
#include "crowd/bake/impostor_bake.h"
#include "crowd/formats/bc5.h"
#include "crowd/formats/bytes.h"
#include "crowd/formats/error.h"
#include "crowd/formats/impostor_spans.h"
#include "crowd/formats/limits.h"
#include "crowd/runtime/impostor_runtime.h"
#include "gltf_writer.h"
#include "real_models.h"
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
          const uint8_t region = m.regions[size_t(f) * m.frameTexels() + t];
          EXPECT_LE(region, humanoid().mesh.parts.size());
          filled += region > 0;
        }
      // Cropped to the silhouette: every crop row and column is touched, so it is well filled.
      EXPECT_GT(filled, size_t(view.width) * view.height / 5);
      // The pivot is the sphere centre, which the character's silhouette surrounds.
      EXPECT_GT(view.pivotX, 0);
      EXPECT_LT(view.pivotX, view.width);
    }
  }
  // Three planes of one layout: BC5 normals and UVs, a region byte per texel; on the GPU less
  // (GpuHoldsRegionIdsIn4BitsAndOnlyTheCoveredSpans).
  EXPECT_EQ(m.atlasWidth % 4, 0u);
  EXPECT_EQ(m.atlasHeight % 4, 0u);
  EXPECT_EQ(m.uvs.size(), m.normals.size());
  EXPECT_EQ(m.normals.size(), m.frames * pack::bc5Bytes(m.atlasWidth, m.atlasHeight));
  EXPECT_EQ(res.bytesPerFrame, m.bytesPerFrame());
  EXPECT_LT(res.bytesPerFrame, 3 * m.frameTexels()); // less than every texel's 3 bytes
  // What the blocks cost, over every covered texel: a few degrees at these 24-texel views (a
  // limb spans a block), 1.6 degrees at the default 128.
  EXPECT_GT(res.compression.texels, 0u);
  EXPECT_GT(res.compression.normalMeanDeg, 0.0);
  EXPECT_LT(res.compression.normalMeanDeg, 4.0);
  EXPECT_LT(res.compression.uvMean, 0.03);
  pack::Reader reader(pack::packBytes(pack::ImpostorPack{{}, m}), "mem");
  EXPECT_EQ(pack::loadImpostorPack(reader).impostor.views.size(), m.views.size());
}

// The player reads a covered texel's normal and UV through its row's span: every covered texel of
// every view, at full detail and at the first mip level, lies in a span whose block is the
// atlas's, and the bytes a frame are the plane of 4-bit ids, the spans' blocks and their index.
TEST(Impostor, GpuHoldsRegionIdsIn4BitsAndOnlyTheCoveredSpans) {
  Reporter r;
  const pack::Impostor m = bakeImpostor(humanoid(), small(), r).impostor;
  ASSERT_EQ(m.regionBits(), 4u); // six regions
  const size_t perFrame = m.views.size() / m.frames;
  uint64_t spanBytes = 0, blocks = 0, stored = 0;
  for (uint32_t f = 0; f < m.frames; ++f) {
    const auto mips = runtime::impostorMips(m, f, 2);
    ASSERT_EQ(mips.size(), 2u);
    for (uint32_t l = 0; l < 2; ++l) {
      const auto &mip = mips[l];
      const auto views = std::span(m.views).subspan(f * perFrame, perFrame);
      const pack::ImpostorSpans s =
          pack::impostorSpans(views, mip.regions, mip.width, mip.height, l);
      ASSERT_EQ(s.viewRows.size(), perFrame);
      if (l == 0) {
        spanBytes += s.sourceBlocks.size() * 32 + (s.rows.size() + perFrame) * 8;
        blocks += size_t(m.atlasWidth / 4) * (m.atlasHeight / 4);
        stored += s.sourceBlocks.size();
      }
      for (size_t v = 0; v < perFrame; ++v) {
        const auto &view = views[v];
        const uint32_t x0 = view.x >> l, x1 = (view.x + view.width - 1u) >> l;
        const uint32_t y0 = view.y >> l, y1 = (view.y + view.height - 1u) >> l;
        for (uint32_t y = y0; y <= y1; ++y)
          for (uint32_t x = x0; x <= x1; ++x) {
            if (!mip.regions[size_t(y) * mip.width + x])
              continue;
            const auto &row = s.rows.at(s.viewRows[v] + y / 4 - y0 / 4);
            ASSERT_GE(x / 4, row.firstColumn);
            const size_t k = row.start + x / 4 - row.firstColumn;
            ASSERT_LT(k, s.sourceBlocks.size());
            EXPECT_EQ(s.sourceBlocks[k], y / 4 * ((mip.width + 3) / 4) + x / 4);
          }
      }
    }
  }
  EXPECT_LT(stored, blocks * 3 / 4) << "the spans leave the empty blocks out";
  EXPECT_EQ(m.bytesPerFrame(),
            uint64_t(pack::regionRowBytes(m.atlasWidth, 4)) * m.atlasHeight + spanBytes / m.frames);
  // Rows of whole 32-bit words.
  EXPECT_EQ(pack::regionRowBytes(8, 4), 4u);
  EXPECT_EQ(pack::regionRowBytes(9, 4), 8u);
  EXPECT_EQ(pack::regionRowBytes(3, 8), 4u);
  EXPECT_EQ(pack::regionRowBytes(8, 8), 8u);
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
  EXPECT_TRUE(res.impostor.uvs.empty());

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

// The mirror figures again from the pack's own region planes: each view placed in its full
// texels x texels frame by its pivot (the sphere's centre sits at the frame's centre), against
// the view from the opposite azimuth half a clip later, flipped left-right.
std::pair<double, double> mirrorIouFromPack(const pack::Impostor &m) {
  const int n = int(m.texels);
  auto mask = [&](uint32_t f, uint32_t e, uint32_t a) {
    std::vector<uint8_t> full(size_t(n) * size_t(n), 0);
    const pack::ImpostorView &v = m.views[m.viewIndex(f, e, a)];
    const int x0 = int(std::lround(n / 2.0 - v.pivotX)), y0 = int(std::lround(n / 2.0 - v.pivotY));
    for (int y = 0; y < v.height; ++y)
      for (int x = 0; x < v.width; ++x)
        if (m.regions[f * m.frameTexels() + size_t(v.y + y) * m.atlasWidth + size_t(v.x + x)] &&
            x0 + x >= 0 && x0 + x < n && y0 + y >= 0 && y0 + y < n)
          full[size_t(y0 + y) * size_t(n) + size_t(x0 + x)] = 1;
    return full;
  };
  double lowest = 1, sum = 0;
  size_t count = 0;
  for (uint32_t f = 0; f < m.frames; ++f)
    for (uint32_t e = 0; e < m.elevations; ++e)
      for (uint32_t a = 0; a < m.azimuths; ++a) {
        const auto p = mask(f, e, a);
        const auto q = mask((f + m.frames / 2) % m.frames, e, (m.azimuths - a) % m.azimuths);
        size_t both = 0, either = 0;
        for (int y = 0; y < n; ++y)
          for (int x = 0; x < n; ++x) {
            const bool u = p[size_t(y * n + x)], w = q[size_t(y * n + n - 1 - x)];
            both += u && w, either += u || w;
          }
        const double iou = either ? double(both) / double(either) : 1.0;
        lowest = std::min(lowest, iou), sum += iou, ++count;
      }
  return {lowest, sum / double(count)};
}

TEST(Impostor, MirroringIsMeasuredNotAssumed) {
  Reporter r;
  auto o = small();
  o.frames = 4; // even: frame f + 2 is half a walk cycle later
  auto res = bakeImpostor(humanoid(), o, r);
  EXPECT_GT(res.mirrorIouMean, 0.95) << "the sample walk is left-right symmetric";
  const auto [lowest, mean] = mirrorIouFromPack(res.impostor);
  std::printf("mirror IoU: bake min %.4f mean %.4f; from the pack min %.4f mean %.4f\n",
              res.mirrorIouMin, res.mirrorIouMean, lowest, mean);
  EXPECT_NEAR(res.mirrorIouMin, lowest, 1e-12);
  EXPECT_NEAR(res.mirrorIouMean, mean, 1e-12);
  o.clip = "idle"; // not symmetric: the figures below 1, and still the pack's
  o.texels = 96;
  const auto idle = bakeImpostor(humanoid(), o, r);
  const auto [idleLowest, idleMean] = mirrorIouFromPack(idle.impostor);
  std::printf("idle mirror IoU: bake min %.4f mean %.4f; from the pack min %.4f mean %.4f\n",
              idle.mirrorIouMin, idle.mirrorIouMean, idleLowest, idleMean);
  EXPECT_LT(idle.mirrorIouMin, 0.99);
  EXPECT_NEAR(idle.mirrorIouMin, idleLowest, 1e-12);
  EXPECT_NEAR(idle.mirrorIouMean, idleMean, 1e-12);
  o.frames = 3;
  EXPECT_EQ(bakeImpostor(humanoid(), o, r).mirrorIouMean, -1) << "odd frame counts: not measured";
}
} // namespace

namespace {
TEST(Impostor, BestPlaneFollowsTheSilhouette) {
  Reporter r;
  auto o = small();
  o.elevations = 4;
  auto m = bakeImpostor(humanoid(), o, r).impostor;
  double radius = m.sphere[3];
  std::vector<double> offsetByRow(4, 0.0), slopeByRow(4, 0.0);
  for (uint32_t e = 0; e < 4; ++e)
    for (uint32_t a = 0; a < 8; ++a) {
      const auto &v = m.views[m.viewIndex(0, e, a)];
      // The outline is near the centre's depth: the plane crosses the image's middle inside the
      // sphere.
      EXPECT_LT(std::abs(v.planeOffset), 0.6 * radius) << e << " " << a;
      EXPECT_LE(std::abs(v.slopeX), pack::kMaxPlaneSlope);
      offsetByRow[e] += v.planeOffset / 8, slopeByRow[e] += v.slopeY / 8;
    }
  // A standing figure seen from above: its head is nearer the camera than its feet, by up to
  // tan(elevation) per unit of image height; the plane tilts back with the body, more from
  // higher up.
  for (uint32_t e = 0; e < 4; ++e) {
    const double tilt = std::tan(0.5 * 3.14159265358979 * (e + 0.5) / 4);
    EXPECT_GT(slopeByRow[e], e ? slopeByRow[e - 1] : 0.0) << e;
    EXPECT_LT(slopeByRow[e], 1.5 * tilt) << e;
  }
}
} // namespace

namespace {
TEST(Impostor, AccuracyIsExactAtTheViewsAndImprovesWithMoreViews) {
  Reporter r;
  auto o = small();
  auto baked = bakeImpostor(humanoid(), o, r);
  const auto &coarse = baked.impostor;
  ImpostorAccuracy a = measureImpostor(humanoid(), coarse, 1);
  // At a stored view the impostor is that view: only the blocks' error is left (measured over
  // every frame by the bake, over frame 0 here).
  EXPECT_GE(a.atViews.iouMin, 0.999);
  EXPECT_NEAR(a.atViews.normalMeanDeg, baked.compression.normalMeanDeg, 0.5);
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
  o.texels = 128;
  o.frames = 2;
  ImpostorAccuracy fine = measureImpostor(humanoid(), bakeImpostor(humanoid(), o, r).impostor, 1);
  EXPECT_GT(fine.betweenViews.iouMean, a.betweenViews.iouMean);
  EXPECT_LT(fine.betweenViews.normalMeanDeg, a.betweenViews.normalMeanDeg);
  // The targets at 32x8 between the views (docs/bakes/impostor.md): the blend of three views and
  // the tilted planes reach them; the nearest view on view-facing planes alone does not.
  EXPECT_GE(fine.betweenViews.iouMean, 0.90);
  EXPECT_LE(fine.betweenViews.normalMeanDeg, 8.0);
  // Popping on a slow orbit: the blend moves between views a step at a time, so the impostor's
  // largest change in a step stays within a few times the geometry's (a nearest view's was 7.9
  // times at 32x8); more views, smaller steps.
  for (const auto *p : {&a.popping, &fine.popping}) {
    EXPECT_GT(p->geometryMean, 0.0);
    EXPECT_GT(p->impostorMax, p->geometryMax);
  }
  EXPECT_LT(fine.popping.impostorMax, 3 * fine.popping.geometryMax);
  EXPECT_EQ(fine.popping.steps, 32 * kOrbitSteps);
  EXPECT_LT(fine.popping.impostorMax, a.popping.impostorMax);
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
  EXPECT_LT(a.atViews.normalMeanDeg, mirrored.compression.normalMeanDeg + 1.0);
  pack::Reader reader(pack::packBytes(pack::ImpostorPack{{}, m}), "mem");
  EXPECT_TRUE(pack::loadImpostorPack(reader).impostor.mirrored);
  o.frames = 3;
  EXPECT_THROW(bakeImpostor(humanoid(), o, r), Error);
}
} // namespace

namespace {
// What the player's impostor shader does, on the CPU: the views it blends are the three sampled
// directions around the camera's, half a clip later and flipped when mirrored; the frame is the
// nearest.
TEST(ImpostorRuntime, ChoosesTheViewsAroundTheDirectionAndTheFrame) {
  Reporter r;
  auto o = small();
  o.frames = 4;
  o.mirror = true;
  const auto m = bakeImpostor(humanoid(), o, r).impostor;
  const double pi = 3.14159265358979323846, step = m.frameStep;
  auto dir = [&](double azDeg, double elDeg) {
    double a = azDeg * pi / 180, e = elDeg * pi / 180;
    return glm::dvec3(std::cos(e) * std::sin(a), std::sin(e), std::cos(e) * std::cos(a));
  };
  // Rows at 22.5 and 67.5 degrees, azimuths 45 apart.
  auto c = runtime::chooseImpostorViews(m, dir(45, 22.5), 1.1 * step, true);
  ASSERT_EQ(c.count, 1); // on a sampled direction: that view alone
  EXPECT_EQ(c.frame, 1u);
  EXPECT_EQ(c.views[0].azimuth, 1u);
  EXPECT_EQ(c.views[0].elevation, 0u);
  EXPECT_FALSE(c.views[0].flip);
  EXPECT_EQ(c.views[0].view, m.viewIndex(1, 0, 1));
  EXPECT_DOUBLE_EQ(c.views[0].weight, 1.0);
  c = runtime::chooseImpostorViews(m, dir(44, 10), 1.1 * step, true); // below the first row
  ASSERT_EQ(c.count, 2);
  EXPECT_EQ(c.views[0].azimuth, 1u); // 44 is nearest to 45: the heavier
  EXPECT_NEAR(c.views[0].weight, 44.0 / 45, 1e-9);
  EXPECT_EQ(c.views[1].azimuth, 0u);
  c = runtime::chooseImpostorViews(m, dir(15, 37.5), 0, true); // a third of the way each way
  ASSERT_EQ(c.count, 3);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(c.views[k].weight, 1.0 / 3, 1e-9);
  c = runtime::chooseImpostorViews(m, dir(-90, 80), 4.9 * step, true); // wraps to frame 1
  ASSERT_EQ(c.count, 1); // above the top row: the top row alone
  EXPECT_EQ(c.views[0].azimuth, 6u);
  EXPECT_EQ(c.views[0].elevation, 1u);
  EXPECT_TRUE(c.views[0].flip);
  EXPECT_EQ(c.views[0].layer, 3u); // frame 1, mirrored: half the clip later
  EXPECT_EQ(c.views[0].view, m.viewIndex(3, 1, 2));
  c = runtime::chooseImpostorViews(m, dir(-100, 22.5), 0, true); // between azimuths 5 and 6
  ASSERT_EQ(c.count, 2);
  EXPECT_EQ(c.views[0].azimuth, 6u);
  EXPECT_TRUE(c.views[0].flip);
  EXPECT_EQ(c.views[1].azimuth, 5u);
  EXPECT_TRUE(c.views[1].flip);
  EXPECT_EQ(c.views[1].layer, 2u);
  c = runtime::chooseImpostorViews(m, dir(0, 10), 9 * step, false); // past the end: clamped
  EXPECT_EQ(c.frame, 3u);
  // The 1:1 distance: a texel (2 r / texels) covers a pixel.
  double d = runtime::oneToOneDistance(m, pi / 2, 480);
  EXPECT_NEAR(2.0 * d * std::tan(pi / 4) / 480, 2.0 * m.sphere[3] / m.texels, 1e-9);
}

// The impostor's diffuse mip level comes from the mesh's texture density: a 2 x 1 quad whose UVs
// span a 256 x 128 texture holds 128 texels per unit, whatever its orientation; without UVs, 0.
TEST(ImpostorRuntime, DiffuseTexelsPerUnitIsTheMeshsTextureDensity) {
  pack::Mesh quad;
  quad.positions = {0, 0, 0, 0, 0, 2, 0, 1, 2, 0, 1, 0};
  quad.uvs = {0, 0, 1, 0, 1, 1, 0, 1};
  quad.indices = {0, 1, 2, 0, 2, 3};
  EXPECT_NEAR(runtime::diffuseTexelsPerUnit(quad, 256, 128), 128.0, 1e-9);
  quad.uvs = {0, 0, 0.5, 0, 0.5, 0.5, 0, 0.5}; // a quarter of the texture: half the texels a unit
  EXPECT_NEAR(runtime::diffuseTexelsPerUnit(quad, 256, 128), 64.0, 1e-9);
  quad.uvs.clear();
  EXPECT_EQ(runtime::diffuseTexelsPerUnit(quad, 256, 128), 0.0);
  quad.uvs = {0, 0, 1, 0, 1, 1, 0, 1};
  quad.positions.assign(12, 0.0f); // no area
  EXPECT_EQ(runtime::diffuseTexelsPerUnit(quad, 256, 128), 0.0);
}

TEST(ImpostorRuntime, MipLevelsNeverAverageRegionIds) {
  pack::Impostor m;
  m.frames = 1;
  m.atlasWidth = 4;
  m.atlasHeight = 4;
  // Rows 0-1: block 1 holds regions 1, 3, 3, empty -> 3 (the mode), never 2; block 2 one covered
  // texel -> empty. Rows 2-3 empty. Each region has its own normal and UV.
  m.regions = {1, 3, 0, 0, 3, 0, 0, 9, 0, 0, 0, 0, 0, 0, 0, 0};
  std::vector<float> oct(32, 0.5f), uv(32, 0.0f);
  for (size_t t = 0; t < 16; ++t)
    if (m.regions[t])
      oct[t * 2] = m.regions[t] * 0.1f, uv[t * 2] = m.regions[t] * 0.05f;
  m.normals = pack::encodeBc5(oct.data(), m.regions.data(), 4, 4);
  m.uvs = pack::encodeBc5(uv.data(), m.regions.data(), 4, 4);
  auto mips = runtime::impostorMips(m, 0, 8);
  ASSERT_EQ(mips.size(), 3u);            // 4x4, 2x2, 1x1
  EXPECT_EQ(mips[0].normals, m.normals); // level 0 is the stored blocks
  EXPECT_EQ(mips[1].width, 2u);
  EXPECT_EQ(mips[1].regions, (std::vector<uint8_t>{3, 0, 0, 0})); // a lone texel does not survive
  // Level 1 takes level 0's decoded values: texel 1's (region 3), not a blend.
  float level0[32], level1[8];
  pack::decodeBc5(m.normals.data(), 4, 4, level0);
  pack::decodeBc5(mips[1].normals.data(), 2, 2, level1);
  EXPECT_NEAR(level1[0], level0[2], 0.6f / 255);
  pack::decodeBc5(m.uvs.data(), 4, 4, level0);
  pack::decodeBc5(mips[1].uvs.data(), 2, 2, level1);
  EXPECT_NEAR(level1[0], level0[2], 0.6f / 255);
  EXPECT_EQ(mips[2].regions, (std::vector<uint8_t>{0})); // one covered texel of four
}

TEST(Bc5, BlocksRoundTripWithinTheirLevelsAndIgnoreUnusedTexels) {
  // A 6x5 image (partial blocks at both edges): a smooth ramp in R, a step in G.
  const uint32_t w = 6, h = 5;
  std::vector<float> rg(w * h * 2);
  std::vector<uint8_t> used(w * h, 1);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      rg[(y * w + x) * 2] = float(x + y * w) / float(w * h);
      rg[(y * w + x) * 2 + 1] = x < 2 ? 0.1f : 0.9f;
    }
  used[w * h - 1] = 0;
  rg[(w * h - 1) * 2] = 1e6f; // unused: its value must not widen the block's range
  auto blocks = pack::encodeBc5(rg.data(), used.data(), w, h);
  ASSERT_EQ(blocks.size(), 2u * 2 * 16);
  std::vector<float> back(rg.size());
  pack::decodeBc5(blocks.data(), w, h, back.data());
  for (size_t t = 0; t + 1 < w * h; ++t) {
    EXPECT_NEAR(back[t * 2], rg[t * 2], 0.5f / 255 + 1.0f / 14) << t; // within half a level
    EXPECT_NEAR(back[t * 2 + 1], rg[t * 2 + 1], 0.6f / 255) << t;     // a step: both endpoints
  }
  // A flat block and a block with no used texel.
  std::vector<float> flat(32, 0.0f);
  std::vector<uint8_t> none(16, 0), all(16, 1);
  std::vector<float> out(32, -1.0f);
  pack::decodeBc5(pack::encodeBc5(flat.data(), all.data(), 4, 4).data(), 4, 4, out.data());
  EXPECT_EQ(out, flat);
  EXPECT_EQ(pack::encodeBc5(flat.data(), none.data(), 4, 4), std::vector<uint8_t>(16, 0));
}

TEST(Bc5, OctahedralNormalsRoundTrip) {
  for (const auto &n : std::vector<std::array<float, 3>>{
           {0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}, {0.6f, -0.48f, -0.64f}}) {
    const auto o = pack::octEncode(n);
    const auto back = pack::octDecode(o[0], o[1]);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(back[size_t(k)], n[size_t(k)], 1e-6f);
  }
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
  for (uint8_t region : res.impostor.regions)
    highest = std::max(highest, region);
  EXPECT_EQ(highest, 255);                  // clamped, not wrapped around to low ids
  EXPECT_EQ(res.impostor.regionBits(), 8u); // more than 15: a byte a texel on the GPU
  EXPECT_EQ(res.compression.regionBits, 8u);
}
} // namespace

namespace {
// A 4x4 one-frame impostor with one view, its texels covered in the top-left block only.
pack::Impostor tinyImpostor() {
  pack::Impostor m;
  m.clip = "walk";
  m.frames = m.azimuths = m.elevations = 1;
  m.texels = 8;
  m.sphere = {0, 1, 0, 1};
  m.atlasWidth = 8, m.atlasHeight = 4;
  m.views = {{0, 0, 8, 4, 4, 2, 0, 0.375f, -1.25f}};
  m.regions.assign(32, 0);
  std::vector<float> oct(64, 0.5f), uv(64, 0.25f);
  for (uint32_t t : {0u, 1u, 8u, 9u})
    m.regions[t] = 2, oct[t * 2] = 0.8f;
  m.normals = pack::encodeBc5(oct.data(), m.regions.data(), 8, 4);
  m.uvs = pack::encodeBc5(uv.data(), m.regions.data(), 8, 4);
  return m;
}

TEST(ImpostorChunk, OnlyBlocksWithACoveredTexelAreStoredAndDamageIsAClearError) {
  const pack::Impostor m = tinyImpostor();
  const auto bytes = pack::encode(m);
  const pack::Impostor back = pack::decodeImpostor(bytes, pack::kImpostorVersion, "chunk");
  EXPECT_EQ(back.normals, m.normals); // the empty block reads zero, as the encoder left it
  EXPECT_EQ(back.uvs, m.uvs);
  EXPECT_EQ(back.regions, m.regions);
  // On the GPU: rows of 4 bytes of 4-bit ids, one block a plane, one row and one view.
  EXPECT_EQ(back.bytesPerFrame(), 4u * 4 + 2 * 16 + 2 * 8);
  pack::Impostor full = m; // all covered: both blocks stored, 16 bytes more per plane
  full.regions.assign(32, 1);
  EXPECT_EQ(pack::encode(full).size(), bytes.size() + 2 * pack::kBc5BlockBytes);
  // A region byte cleared after encoding: the chunk stores a block more than the regions say.
  auto damaged = bytes;
  const auto at = std::search(damaged.begin(), damaged.end(), m.regions.begin(), m.regions.end());
  ASSERT_NE(at, damaged.end());
  at[0] = 0, at[1] = 0, at[8] = 0, at[9] = 0;
  try {
    pack::decodeImpostor(damaged, pack::kImpostorVersion, "chunk");
    FAIL() << "a block count that does not match the regions decoded";
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("field 'normals'"), std::string::npos) << e.what();
  }
  auto odd = m; // not whole blocks
  odd.atlasHeight = 3;
  odd.regions.resize(24);
  EXPECT_THROW(pack::decodeImpostor(pack::encode(odd), pack::kImpostorVersion, "chunk"), Error);
}

TEST(ImpostorChunk, PlaneSlopesRoundTripAreBoundedAndAbsentBeforeVersion4) {
  const pack::Impostor m = tinyImpostor();
  const auto bytes = pack::encode(m);
  const pack::Impostor back = pack::decodeImpostor(bytes, pack::kImpostorVersion, "chunk");
  EXPECT_EQ(back.views[0].slopeX, 0.375f);
  EXPECT_EQ(back.views[0].slopeY, -1.25f);
  // The slopes' 8 bytes, found by their values.
  const float slopes[2] = {0.375f, -1.25f};
  const auto *raw = reinterpret_cast<const uint8_t *>(slopes);
  const auto at = std::search(bytes.begin(), bytes.end(), raw, raw + 8);
  ASSERT_NE(at, bytes.end());
  auto steep = bytes; // a plane nearly along the view: damage, a clear error
  const float tooSteep = 1e9f;
  std::copy_n(reinterpret_cast<const uint8_t *>(&tooSteep), 4,
              steep.begin() + (at - bytes.begin()));
  try {
    pack::decodeImpostor(steep, pack::kImpostorVersion, "chunk");
    FAIL() << "a slope of 1e9 decoded";
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("slope"), std::string::npos) << e.what();
  }
  // Version 3 had no slopes: the same chunk without them reads with view-facing planes. The
  // regions' count follows the slopes, then zeros up to a multiple of 16 bytes, then the regions.
  auto padded = [](long offset) { return (offset + 15) / 16 * 16; };
  const long slopesAt = at - bytes.begin();
  std::vector<uint8_t> v3(bytes.begin(), at);
  v3.insert(v3.end(), at + 8, at + 16);                                    // the count
  v3.resize(size_t(padded(slopesAt + 8)), 0);                              // its padding
  v3.insert(v3.end(), bytes.begin() + padded(slopesAt + 16), bytes.end()); // the regions on
  const pack::Impostor old = pack::decodeImpostor(v3, 3, "chunk");
  EXPECT_EQ(old.views[0].slopeX, 0.0f);
  EXPECT_EQ(old.views[0].slopeY, 0.0f);
  EXPECT_EQ(old.views[0].planeOffset, m.views[0].planeOffset);
  EXPECT_EQ(old.regions, m.regions);
}

TEST(ImpostorChunk, AVersion2ChunkIsReadAndEncodedAsVersion3) {
  // Version 2: RGBA8 normals with the region in A, RGBA16 UVs; a 3-texel-tall atlas.
  pack::ByteWriter w;
  w.putString("walk");
  w.putString("");
  w.put<float>(0);
  w.put<float>(0.1f);
  for (uint32_t v : {1u, 1u, 1u, 8u})
    w.put<uint32_t>(v);
  w.put<uint8_t>(0);
  for (float f : {0.0f, 1.0f, 0.0f, 1.0f})
    w.put<float>(f);
  w.put<uint32_t>(4);
  w.put<uint32_t>(3);
  w.put<uint64_t>(1);
  for (uint16_t u : {0, 0, 4, 3})
    w.put<uint16_t>(u);
  for (float f : {2.0f, 1.5f, 0.0f})
    w.put<float>(f);
  std::vector<uint8_t> rgba(12 * 4, 0);
  std::vector<uint16_t> uv(12 * 4, 0);
  for (size_t t : {0u, 5u, 11u}) { // normal (0, 0, -1); regions 1, 2, 3
    rgba[t * 4] = rgba[t * 4 + 1] = 128, rgba[t * 4 + 2] = 0, rgba[t * 4 + 3] = uint8_t(t % 4 + 1);
    uv[t * 4] = 65535 / 2, uv[t * 4 + 1] = 65535 / 4;
  }
  w.putArray(rgba);
  w.putArray(uv);
  const pack::Impostor m = pack::decodeImpostor(w.take(), 2, "chunk");
  ASSERT_EQ(m.atlasHeight, 4u); // padded to whole blocks
  const pack::ImpostorTexels t = pack::decodeTexels(m, 0);
  for (size_t v : {0u, 5u, 11u}) {
    const size_t i = v / 4 * 4 + v % 4; // same row and column in the 4-wide atlas
    EXPECT_EQ(t.regions[i], v % 4 + 1);
    EXPECT_LT(t.normal(i)[2], -0.99f);
    EXPECT_NEAR(t.uv[i * 2], 0.5f, 1.0f / 255);
    EXPECT_NEAR(t.uv[i * 2 + 1], 0.25f, 1.0f / 255);
  }
  EXPECT_EQ(std::count(m.regions.begin(), m.regions.end(), 0), 16 - 3);
}
} // namespace

namespace {
// The humanoid in its rest pose with its vertices moved by `move`.
Character reshaped(const std::function<glm::vec3(glm::vec3)> &move) {
  Character c = humanoid();
  c.clips.clear();
  for (auto &p : c.mesh.positions)
    p = move(p);
  return c;
}

TEST(Impostor, AOneTexelWideCropBakesStoresAndDrawsAtOneLevel) {
  // Squashed to a vertical needle a few centimetres across: a texel or two (4 cm) wide.
  Reporter r;
  r.quiet = true;
  const Character needle =
      reshaped([](glm::vec3 p) { return glm::vec3(p.x * 0.1f, p.y, p.z * 0.1f); });
  auto o = small();
  o.clip = "";
  const auto res = bakeImpostor(needle, o, r);
  const auto &m = res.impostor;
  uint16_t narrowest = UINT16_MAX;
  for (const auto &v : m.views)
    if (v.width)
      narrowest = std::min(narrowest, v.width);
  EXPECT_LE(narrowest, 2) << "the needle should be a texel or two wide";
  EXPECT_GE(narrowest, 1);
  EXPECT_EQ(m.atlasWidth % 4, 0u);
  // Stored and read back whole; the mips stop at the narrowest crop: one level.
  pack::Reader reader(pack::packBytes(pack::ImpostorPack{{}, m}), "mem");
  EXPECT_EQ(pack::loadImpostorPack(reader).impostor.regions, m.regions);
  EXPECT_EQ(runtime::impostorMipLevels(m), 1u);
  EXPECT_EQ(runtime::impostorMips(m, 0, runtime::impostorMipLevels(m)).size(), 1u);
  ImpostorAccuracy a = measureImpostor(needle, m, 1);
  EXPECT_GE(a.atViews.iouMean, 0.9);
}

TEST(Impostor, AMeshThatFillsTheWholeViewCropsToTheWholeView) {
  // Every vertex pushed out onto the bounding sphere: the silhouette is the sphere's disk, which
  // touches all four sides of every view.
  Reporter r;
  r.quiet = true;
  const Character h = humanoid();
  glm::vec3 lo(1e9f), hi(-1e9f);
  for (const auto &p : h.mesh.positions)
    lo = glm::min(lo, p), hi = glm::max(hi, p);
  const glm::vec3 mid = 0.5f * (lo + hi);
  const Character ball = reshaped([&](glm::vec3 p) {
    glm::vec3 d = p - mid;
    return glm::length(d) > 0 ? mid + glm::normalize(d) * 0.5f : p;
  });
  auto o = small();
  o.clip = "";
  const auto res = bakeImpostor(ball, o, r);
  const auto &m = res.impostor;
  for (const auto &v : m.views) {
    EXPECT_GE(v.width, m.texels - 2);
    EXPECT_GE(v.height, m.texels - 2);
  }
  EXPECT_GT(res.occupancy, 0.9);
  EXPECT_EQ(runtime::impostorMipLevels(m), 5u); // 48-texel crops: 48, 24, 12, 6, 3
  ImpostorAccuracy a = measureImpostor(ball, m, 1);
  EXPECT_GE(a.atViews.iouMin, 0.99);
}

TEST(Impostor, UvErrorIsReportedInTexelsOfAWideTexture) {
  // A 1024-texel-wide diffuse texture: BC5 UVs keep 8-bit endpoints, so the report says what
  // that costs in its texels instead of hiding it in texture widths.
  Reporter r;
  r.quiet = true;
  Character wide = humanoid();
  ASSERT_TRUE(wide.diffuse.has_value());
  wide.diffuse->width = 1024;
  wide.diffuse->height = 1024;
  wide.diffuse->rgba.assign(size_t(1024) * 1024 * 4, 200);
  const auto o = small();
  const auto res = bakeImpostor(wide, o, r);
  const auto f = impostorFigures(res, o);
  const auto &c = f.at("compression");
  EXPECT_DOUBLE_EQ(c.at("uv_error_max_texels").get<double>(), res.compression.uvMax * 1024);
  EXPECT_GT(c.at("uv_error_mean_texels").get<double>(), 0.0);
  EXPECT_EQ(c.at("regions").get<std::string>(), "exact, 4 bits"); // six regions
}
} // namespace

namespace {
// Every real model (test::realModels) bakes an impostor of its first clip that holds up between
// the stored views, at the default 32x8 views and a small per-view resolution (2 frames).
TEST(Impostor, EveryRealModelHoldsUpBetweenViews) {
  for (const auto &f : test::realModels()) {
    SCOPED_TRACE(f);
    Reporter r;
    r.quiet = true;
    const Character c = importGltf(f, {}, r);
    ImpostorOptions o;
    o.frames = 2;
    o.texels = 64;
    const auto baked = bakeImpostor(c, o, r);
    const ImpostorAccuracy a = measureImpostor(c, baked.impostor, 1);
    std::printf("%s: between views IoU %.3f, normal %.1f degrees; %zu bytes a frame\n",
                std::filesystem::path(f).filename().c_str(), a.betweenViews.iouMean,
                a.betweenViews.normalMeanDeg, size_t(baked.bytesPerFrame));
    EXPECT_GE(a.atViews.iouMin, 0.95);
    // RecursiveSkeletons' 84 skins curl thin branches (a few texels wide) every way: between
    // views they overlap least (0.81 and 25 degrees at 128 texels). A wrong plane or offset gives
    // under 0.3.
    // Normals between views: 15.0, 16.8 and 15.5 degrees on Dragon_Evolved, HVGirl and Stag
    // (their fine, flat-shaded or many-part surfaces), 13.8 at most on the others; the limit is
    // the worst with a little room. Where those degrees come from (detail a view cannot hold, or
    // misregistration, the normal filter, the plane fit) and the 8-degree target are the
    // impostor issue's (#82).
    const bool thin = f.find("RecursiveSkeletons") != std::string::npos;
    EXPECT_GE(a.betweenViews.iouMean, thin ? 0.75 : 0.85);
    EXPECT_LE(a.betweenViews.normalMeanDeg, thin ? 30.0 : 18.0);
  }
}
} // namespace
