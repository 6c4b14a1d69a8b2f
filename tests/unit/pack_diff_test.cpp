// crowdbake diff's comparisons: a pack against itself and a re-bake at another thread count pass;
// another precision moves vertices and names where; changed influences, triangles (not a triangle
// started at another corner), region ids
// and loop starts fail; a missing chunk is incomparable; provenance is listed, never failing;
// tolerances files are checked.
#include <algorithm>

#include <gtest/gtest.h>

#include "crowd/bake/anim_bake.h"
#include "crowd/bake/impostor_bake.h"
#include "crowd/bake/pack_diff.h"
#include "crowd/formats/character_pack.h"
#include "crowd/formats/error.h"
#include "sample_character.h"

using namespace crowd;

namespace {

// The packs diffed here store the animation texture, whose precisions differ measurably.
AnimBakeOptions textureBake() {
  AnimBakeOptions o;
  o.store = "texture";
  return o;
}

pack::AnimationPack bakeAt(const std::string &precision, int threads) {
  AnimBakeOptions o = textureBake();
  o.precision = precision;
  o.fps = 30;
  o.threads = threads;
  Reporter r;
  r.quiet = true;
  return bakeAnimation(test::sampleHumanoid(), o, r).pack;
}

const pack::AnimationPack &qts() {
  static const pack::AnimationPack p = bakeAt("qts", 2);
  return p;
}

pack::Reader reader(const std::vector<uint8_t> &bytes, const std::string &name) {
  return pack::Reader(bytes, name);
}

PackDiff diff(const std::vector<uint8_t> &a, const std::vector<uint8_t> &b,
              const DiffTolerances &t = {}) {
  return diffPacks(reader(a, "golden"), reader(b, "new"), t);
}

const DiffItem *item(const PackDiff &d, const std::string &chunk, const std::string &what) {
  for (const auto &i : d.items)
    if (i.chunk == chunk && i.what == what)
      return &i;
  return nullptr;
}

TEST(PackDiff, APackAndARebakeAtAnotherThreadCountPass) {
  const auto bytes = pack::packBytes(qts());
  const PackDiff self = diff(bytes, bytes);
  EXPECT_EQ(self.verdict, DiffVerdict::Pass);
  for (const auto &i : self.items)
    EXPECT_TRUE(i.identical) << i.chunk;
  EXPECT_EQ(diff(bytes, pack::packBytes(bakeAt("qts", 1))).verdict, DiffVerdict::Pass);
}

TEST(PackDiff, AnotherPrecisionNamesTheWorstClipTimeVertexAndJoint) {
  const PackDiff d = diff(pack::packBytes(qts()), pack::packBytes(bakeAt("half", 2)));
  const DiffItem *anim = item(d, "ANIM", "animation displacement");
  ASSERT_NE(anim, nullptr);
  EXPECT_GT(anim->value, DiffTolerances{}.animationMm.warn);
  EXPECT_GE(int(d.verdict), int(DiffVerdict::Warn));
  EXPECT_NE(anim->worst.find("clip '"), std::string::npos) << anim->worst;
  EXPECT_NE(anim->worst.find(" s, vertex "), std::string::npos) << anim->worst;
  EXPECT_NE(anim->worst.find("(joint '"), std::string::npos) << anim->worst;
  // A looser tolerance passes the same change.
  DiffTolerances loose;
  loose.animationMm = {50, 100};
  EXPECT_EQ(diff(pack::packBytes(qts()), pack::packBytes(bakeAt("half", 2)), loose).verdict,
            DiffVerdict::Pass);
}

TEST(PackDiff, ChangedInfluencesTrianglesAndMissingChunksAreCaught) {
  const auto golden = pack::packBytes(qts());
  pack::AnimationPack other = qts();
  other.skin.texels[0] = float(qts().skeleton.jointCount() - 1); // another joint
  const PackDiff influences = diff(golden, pack::packBytes(other));
  const DiffItem *skin = item(influences, "SKIN", "skin weights");
  ASSERT_NE(skin, nullptr);
  EXPECT_EQ(skin->verdict, DiffVerdict::Fail) << skin->worst;

  pack::AnimationPack flipped = qts();
  std::swap(flipped.mesh.indices[0], flipped.mesh.indices[1]);
  EXPECT_EQ(diff(golden, pack::packBytes(flipped)).verdict, DiffVerdict::Fail);
  // The same triangles, two started at another corner (meshopt's index codec): counted, passed.
  pack::AnimationPack turned = qts();
  std::rotate(&turned.mesh.indices[0], &turned.mesh.indices[1], &turned.mesh.indices[3]);
  std::rotate(&turned.mesh.indices[3], &turned.mesh.indices[5], &turned.mesh.indices[6]);
  const PackDiff rotated = diff(golden, pack::packBytes(turned));
  EXPECT_EQ(rotated.verdict, DiffVerdict::Pass);
  const DiffItem *corners = item(rotated, "MESH", "triangles starting at another corner");
  ASSERT_NE(corners, nullptr);
  EXPECT_EQ(corners->value, 2);

  pack::AnimationPack noLod = test::sampleHumanoidLodPack();
  const auto withLod = pack::packBytes(noLod);
  noLod.lod.reset();
  EXPECT_EQ(diff(withLod, pack::packBytes(noLod)).verdict, DiffVerdict::Incomparable);
}

TEST(PackDiff, ProvenanceIsListedNotFailing) {
  pack::AnimationPack p = qts();
  p.provenance.bakerVersion = "golden-1";
  pack::AnimationPack q = qts();
  q.provenance.bakerVersion = "new-2";
  const PackDiff d = diff(pack::packBytes(p), pack::packBytes(q));
  EXPECT_EQ(d.verdict, DiffVerdict::Pass);
  const DiffItem *prov = item(d, "PROV", "provenance");
  ASSERT_NE(prov, nullptr);
  EXPECT_TRUE(prov->informational);
  EXPECT_NE(prov->worst.find("golden-1 -> new-2"), std::string::npos) << prov->worst;
}

TEST(PackDiff, ImpostorRegionIdsAreExactAndTexelsWithinPercent) {
  ImpostorOptions o;
  o.clip = "walk";
  o.frames = 2;
  o.azimuths = 4;
  o.elevations = 1;
  o.texels = 24;
  Reporter r;
  r.quiet = true;
  const pack::Impostor m = bakeImpostor(test::sampleHumanoid(), o, r).impostor;
  const auto golden = pack::packBytes(pack::ImpostorPack{{}, m});
  // The normals are BC5 blocks: moving a block's first red endpoint moves its texels' normals.
  size_t drawn = 0;
  while (m.regions[drawn] == 0)
    ++drawn;
  const size_t block = (drawn / m.atlasWidth / 4) * (m.atlasWidth / 4) + drawn % m.atlasWidth / 4;
  pack::Impostor shade = m; // one block's normals a step off: within the fail tolerance
  const int step = shade.normals[block * 16] == 255 ? -1 : 1; // both endpoints, in order
  for (size_t e = 0; e < 2; ++e)
    shade.normals[block * 16 + e] = uint8_t(shade.normals[block * 16 + e] + step);
  EXPECT_EQ(diff(golden, pack::packBytes(pack::ImpostorPack{{}, shade})).verdict,
            DiffVerdict::Warn);
  pack::Impostor many = m; // every block's normals 10 steps off: past the fail tolerance
  for (size_t b = 0; b < many.normals.size(); b += 16)
    for (size_t e = 0; e < 2; ++e)
      many.normals[b + e] =
          uint8_t(many.normals[b + e] > 128 ? many.normals[b + e] - 10 : many.normals[b + e] + 10);
  const auto manyBytes = pack::packBytes(pack::ImpostorPack{{}, many});
  EXPECT_EQ(diff(golden, manyBytes).verdict, DiffVerdict::Fail);
  DiffTolerances relative; // idiff's -failrelative: small against the values themselves
  relative.texelRelative = {5, 5};
  EXPECT_EQ(diff(golden, manyBytes, relative).verdict, DiffVerdict::Pass);
  pack::Impostor region = m; // one texel's region id changed
  region.regions[drawn] = uint8_t(region.regions[drawn] + 1);
  const PackDiff d = diff(golden, pack::packBytes(pack::ImpostorPack{{}, region}));
  EXPECT_EQ(d.verdict, DiffVerdict::Fail);
}

TEST(PackDiff, TolerancesFilesAreChecked) {
  const auto t =
      tolerancesFromJson(nlohmann::json::parse(R"({"animation_mm": {"fail": 2}})"), "t.json");
  EXPECT_EQ(t.animationMm.fail, 2);
  EXPECT_EQ(t.animationMm.warn, DiffTolerances{}.animationMm.warn);
  for (const char *bad : {R"({"anim": {"fail": 2}})", R"({"uv": {"warn": 2, "fail": 1}})",
                          R"({"uv": {"fail": -1}})", R"({"uv": 3})", R"([1])"})
    EXPECT_THROW(tolerancesFromJson(nlohmann::json::parse(bad), "t.json"), Error) << bad;
  // Every default is written back, so a report says what was used.
  EXPECT_EQ(tolerancesJson(DiffTolerances{}).size(), 10u);
}

TEST(PackDiff, ATruncatedOrInconsistentPackIsAClearError) {
  auto bytes = pack::packBytes(qts());
  bytes.resize(bytes.size() / 2);
  EXPECT_THROW(reader(bytes, "cut.crowdpack"), Error);
  // Every chunk reads on its own, but a vertex names a joint the skeleton lacks: the player's
  // reader refuses it, and so does diff before it skins anything (a changed animation texture
  // makes it skin).
  pack::AnimationPack stray = qts();
  stray.skin.texels[0] = float(stray.skeleton.jointCount());
  stray.animation.texels[0] ^= 1;
  try {
    diff(pack::packBytes(qts()), pack::packBytes(stray));
    ADD_FAILURE() << "a joint id past the skeleton was compared";
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("uses joint"), std::string::npos) << e.what();
  }
}

} // namespace
