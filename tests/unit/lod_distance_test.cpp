// The measure lod_bench reports its LOD figures with (tests/bench/lod_distance.h): zero for the
// full mesh at rest and at every frame, and the same figures whatever units the mesh is stored
// in when its skin brings it to the same pose (an armature scale: the bench once measured the
// stored mesh against the skinned frames, 100x off on a centimetre mesh under a 0.01 armature).
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "../bench/lod_distance.h"
#include "sample_character.h"

using namespace crowd;

namespace {

// Every fourth triangle left out: a coarse stand-in for a LOD.
std::vector<uint32_t> thinned(const std::vector<uint32_t> &indices) {
  std::vector<uint32_t> out;
  for (size_t t = 0; 3 * t + 2 < indices.size(); ++t)
    if (t % 4 != 3)
      out.insert(out.end(), indices.begin() + ptrdiff_t(3 * t),
                 indices.begin() + ptrdiff_t(3 * t + 3));
  return out;
}

} // namespace

TEST(LodDistance, TheFullMeshIsZeroAtRestAndAtEveryFrame) {
  const Character &c = test::sampleHumanoid();
  const bench::LodDistanceMeasure measure(c, 5.0, 200);
  ASSERT_GT(measure.frameCount(), 10u);
  const bench::LodDistance full = measure.measure(c.mesh.indices);
  EXPECT_LT(full.restPct, 1e-9);
  EXPECT_LT(full.animatedMaxPct, 1e-9);
  EXPECT_LT(full.animatedMeanPct, 1e-9);
  const bench::LodDistance cut = measure.measure(thinned(c.mesh.indices));
  EXPECT_GT(cut.restPct, 0.01);
  EXPECT_GE(cut.animatedMaxPct, cut.animatedMeanPct);
  EXPECT_GT(cut.animatedMeanPct, 0.0);
}

TEST(LodDistance, MeshUnitsTheSkinRescalesChangeNoFigure) {
  const Character &metres = test::sampleHumanoid();
  Character centimetres = metres; // the mesh stored 100x larger, the skin scaling it back
  for (auto &p : centimetres.mesh.positions)
    p *= 100.0f;
  for (auto &target : centimetres.mesh.morphs)
    for (auto &p : target.positions)
      p *= 100.0f;
  for (auto &inverseBind : centimetres.inverseBind)
    inverseBind = inverseBind * glm::scale(glm::dmat4(1.0), glm::dvec3(0.01));
  const auto lod = thinned(metres.mesh.indices);
  const bench::LodDistance m = bench::LodDistanceMeasure(metres, 5.0, 200).measure(lod);
  const bench::LodDistance cm = bench::LodDistanceMeasure(centimetres, 5.0, 200).measure(lod);
  EXPECT_NEAR(cm.restPct, m.restPct, 1e-6 * m.restPct);
  EXPECT_NEAR(cm.animatedMaxPct, m.animatedMaxPct, 1e-6 * m.animatedMaxPct);
  EXPECT_NEAR(cm.animatedMeanPct, m.animatedMeanPct, 1e-6 * m.animatedMeanPct);
}
