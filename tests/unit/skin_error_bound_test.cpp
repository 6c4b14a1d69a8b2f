// SkinErrorBound, the bound that lets the error budget skip vertices: on every real model, at
// every precision, at frame times (where only rounding is left), mid-frames and times in between,
// no vertex errs past its bound nor (without morph targets) any block's vertex past the block's;
// and the bound is tight enough to skip most of the vertices.
#include <cstdio>

#include <gtest/gtest.h>

#include "../../bake/src/anim/skin_error_bound.h"
#include "crowd/bake/anim_frames.h"
#include "crowd/bake/evaluate.h"
#include "crowd/bake/import.h"
#include "crowd/bake/morph_frames.h"
#include "crowd/runtime/texture_skinning.h"
#include "real_models.h"

using namespace crowd;

TEST(SkinErrorBound, NoVertexErrsPastItsBoundOnAnyRealModel) {
  size_t models = 0, checked = 0, skippable = 0;
  for (const std::string &file : test::realModels()) {
    Reporter r;
    r.quiet = true;
    const Character c = importGltf(file, {}, r);
    if (c.clips.empty())
      continue;
    ++models;
    const SkinnedMesh &m = c.mesh;
    const pack::SkinTexture skin = buildSkinTexture(m, 4096);
    const SkinErrorBound bound(m, skin, c.jointCount());
    const AnimationClip &clip = c.clips.front();
    const ClipFrames f = planFrames(clip, 10); // coarse: real errors between frames
    std::vector<std::vector<glm::dmat4>> joints;
    std::vector<std::vector<double>> morphs;
    for (uint32_t i = 0; i < f.count; ++i) {
      joints.push_back(jointMatrices(c, &clip, f.start + i * f.step));
      morphs.push_back(morphWeights(c, &clip, f.start + i * f.step));
    }
    const auto morphFrames = buildMorphs(m, morphs);
    const bool morphed = !m.morphs.empty();
    ASSERT_EQ(bound.blocks(), !morphed) << file;
    pack::Clip packClip;
    packClip.fps = float(f.fps);
    packClip.frameCount = f.count;
    for (const Precision &p : precisions()) {
      const auto texture = buildAnimationTexture(joints, c.jointCount(), p, 4096);
      for (uint32_t frame = 0; frame + 1 < f.count; ++frame)
        for (float alpha : {0.0f, 0.3f, 0.5f}) {
          const auto exactJoints = jointMatrices(c, &clip, f.start + (frame + alpha) * f.step);
          const auto weights = morphWeights(c, &clip, f.start + (frame + alpha) * f.step);
          const auto rows = runtime::sampleJoints(texture, packClip, frame, alpha);
          const auto terms = bound.terms(rows, exactJoints);
          const runtime::ClipTime at{&packClip, frame, alpha};
          std::vector<double> error(m.vertexCount()), most(m.vertexCount());
          double largest = 0;
          for (uint32_t v = 0; v < m.vertexCount(); ++v) {
            const glm::vec3 drawn = morphedBind(m, morphFrames, at, v);
            const glm::dvec3 off = glm::dvec3(runtime::skinVertex(rows, skin, v, drawn)) -
                                   skinPosition(m, exactJoints, weights, v);
            error[v] = glm::dot(off, off);
            largest = std::max(largest, error[v]);
            most[v] = morphed ? bound.morphedVertex(v, terms, drawn, morphedPosition(m, weights, v))
                              : bound.vertex(v, terms);
            ASSERT_LE(error[v], most[v]) << file << " " << p.name << " frame " << frame << " alpha "
                                         << alpha << " vertex " << v;
          }
          for (uint32_t v = 0; v < m.vertexCount(); ++v) {
            if (!morphed) {
              ASSERT_LE(error[v], bound.block(v / SkinErrorBound::kBlock, terms))
                  << file << " " << v;
            }
            skippable += alpha > 0 && most[v] <= largest;
            checked += alpha > 0;
          }
        }
    }
  }
  std::printf("%zu models: %zu of %zu vertex times within the time's largest error\n", models,
              skippable, checked);
  EXPECT_GE(models, 8u); // the committed ones at least (15 with ../shared's)
  // Against the time's own largest error alone (the bake starts each time from the largest of
  // the times before, so it skips more): most vertices.
  EXPECT_GT(double(skippable), 0.5 * double(checked)) << skippable << " of " << checked;
}
