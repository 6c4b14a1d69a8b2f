// The player's render queues for clothed characters (render_queues.h), on the seed's Table 1
// setting: two characters, one in a dress, one in a jumper with a skirt.
#include <map>
#include <tuple>

#include <gtest/gtest.h>

#include "crowd/runtime/render_queues.h"

using namespace crowd;
using namespace crowd::runtime;

namespace {

// Body sub-meshes head, torso, arms, legs, feet (one triangle each, on body vertices 0..4);
// outfit-specific copies legs@dress and arms@jumper_skirt and legs@jumper_skirt (body
// vertices); garments dress, jumper, skirt (their own vertices 5..7).
const std::vector<std::string> kNames = {"head",
                                         "torso",
                                         "arms",
                                         "legs",
                                         "feet",
                                         "legs@dress",
                                         "dress",
                                         "arms@jumper_skirt",
                                         "legs@jumper_skirt",
                                         "jumper",
                                         "skirt"};

pack::AnimationPack table1Pack() {
  pack::AnimationPack p;
  p.mesh.positions.assign(8 * 3, 0.0f);
  const uint32_t tris[11][3] = {{0, 1, 2}, {1, 2, 3}, {2, 3, 4}, {3, 4, 0}, {4, 0, 1}, {3, 4, 2},
                                {5, 6, 7}, {2, 0, 1}, {3, 1, 4}, {6, 7, 5}, {7, 5, 6}};
  for (uint32_t s = 0; s < 11; ++s) {
    p.mesh.subMeshes.push_back({kNames[s], s * 3, 3});
    p.mesh.indices.insert(p.mesh.indices.end(), tris[s], tris[s] + 3);
  }
  pack::Outfits t;
  t.bodySubMeshes = 5;
  using C = pack::Coverage;
  t.outfits.push_back(
      {"dress", {C::Visible, C::Hidden, C::Visible, C::Partial, C::Visible}, {0, 2, 4, 5, 6}});
  t.outfits.push_back({"jumper_skirt",
                       {C::Visible, C::Hidden, C::Partial, C::Partial, C::Visible},
                       {0, 4, 7, 8, 9, 10}});
  p.outfits = t;
  return p;
}

// Queue contents per sub-mesh name (levels joined).
std::map<std::string, std::vector<uint32_t>> byName(const RenderQueues &q) {
  std::map<std::string, std::vector<uint32_t>> m;
  for (const auto &queue : q.queues)
    m[kNames[queue.subMesh]].insert(m[kNames[queue.subMesh]].end(),
                                    q.queueIds.begin() + queue.first,
                                    q.queueIds.begin() + queue.first + queue.count);
  return m;
}

using Queues = std::map<std::string, std::vector<uint32_t>>;

// The naive method's queues for table1Pack's two characters: the whole body under each outfit's
// garments, no copies.
const Queues kNaiveTable1 = {{"head", {0, 1}}, {"torso", {0, 1}}, {"arms", {0, 1}},
                             {"legs", {0, 1}}, {"feet", {0, 1}},  {"dress", {0}},
                             {"jumper", {1}},  {"skirt", {1}}};

} // namespace

TEST(RenderQueues, Table1TwoCharactersDressAndJumperWithSkirt) {
  const auto pack = table1Pack();
  RenderQueues q(outfitSubMeshes(pack, false), 11);
  const std::vector<uint32_t> outfitOf = {0, 1}; // character 0: dress; 1: jumper + skirt
  const std::vector<uint32_t> ids = {0, 1}, runEnds = {2};
  q.build(ids, runEnds, outfitOf);
  // The hidden torso has no queue; bare parts are shared; each partial part and garment
  // queues only the character that needs it.
  EXPECT_EQ(byName(q), (Queues{{"head", {0, 1}},
                               {"arms", {0}},
                               {"feet", {0, 1}},
                               {"legs@dress", {0}},
                               {"dress", {0}},
                               {"arms@jumper_skirt", {1}},
                               {"legs@jumper_skirt", {1}},
                               {"jumper", {1}},
                               {"skirt", {1}}}));
  EXPECT_EQ(q.capacity(2), 2u * 6u);

  // The naive method draws the whole body under each outfit's garments, no copies.
  RenderQueues naive(outfitSubMeshes(pack, true), 11);
  naive.build(ids, runEnds, outfitOf);
  EXPECT_EQ(byName(naive), kNaiveTable1);
}

// A pack with LOD numbers its vertices in collapse order, so garment vertices come among the
// body's: the naive method must still tell garments (vertices of their own) from copies of body
// parts (body vertices only). It once told them by index and drew no garment at all.
TEST(RenderQueues, TheNaiveMethodFindsGarmentsWhateverTheVertexOrder) {
  auto pack = table1Pack();
  for (uint32_t &i : pack.mesh.indices)
    i = 7 - i; // the garments' vertices 5-7 become 0-2
  RenderQueues naive(outfitSubMeshes(pack, true), 11);
  const std::vector<uint32_t> outfitOf = {0, 1}, ids = {0, 1}, runEnds = {2};
  naive.build(ids, runEnds, outfitOf);
  EXPECT_EQ(byName(naive), kNaiveTable1);
}

TEST(RenderQueues, OnlyVisibleInstancesQueuedPerLevelGroupedByOutfit) {
  const auto pack = table1Pack();
  RenderQueues q(outfitSubMeshes(pack, false), 11);
  const std::vector<uint32_t> outfitOf = {0, 1, 0, 1, 0};
  // Instance 0 is culled; 4 and 1 at level 0, then 3 and 2 at level 1.
  const std::vector<uint32_t> ids = {4, 1, 3, 2}, runEnds = {2, 4};
  q.build(ids, runEnds, outfitOf);
  std::vector<std::tuple<std::string, uint32_t, std::vector<uint32_t>>> got;
  for (const auto &queue : q.queues)
    got.push_back(
        {kNames[queue.subMesh],
         queue.level,
         {q.queueIds.begin() + queue.first, q.queueIds.begin() + queue.first + queue.count}});
  using T = std::tuple<std::string, uint32_t, std::vector<uint32_t>>;
  const std::vector<T> want = {{"head", 0, {4, 1}},
                               {"head", 1, {2, 3}},
                               {"arms", 0, {4}},
                               {"arms", 1, {2}},
                               {"feet", 0, {4, 1}},
                               {"feet", 1, {2, 3}},
                               {"legs@dress", 0, {4}},
                               {"legs@dress", 1, {2}},
                               {"dress", 0, {4}},
                               {"dress", 1, {2}},
                               {"arms@jumper_skirt", 0, {1}},
                               {"arms@jumper_skirt", 1, {3}},
                               {"legs@jumper_skirt", 0, {1}},
                               {"legs@jumper_skirt", 1, {3}},
                               {"jumper", 0, {1}},
                               {"jumper", 1, {3}},
                               {"skirt", 0, {1}},
                               {"skirt", 1, {3}}};
  EXPECT_EQ(got, want);

  q.build({}, std::vector<uint32_t>{0, 0}, outfitOf); // nothing visible: no queue
  EXPECT_TRUE(q.queues.empty());
  EXPECT_TRUE(q.queueIds.empty());
}

TEST(RenderQueues, APackWithoutOutfitsQueuesEveryVisibleInstanceForEverySubMesh) {
  auto pack = table1Pack();
  pack.outfits.reset();
  RenderQueues q(outfitSubMeshes(pack, false), 11);
  const std::vector<uint32_t> outfitOf = {0, 0, 0}, ids = {2, 0}, runEnds = {2};
  q.build(ids, runEnds, outfitOf);
  ASSERT_EQ(q.queues.size(), 11u);
  for (uint32_t s = 0; s < 11; ++s) {
    EXPECT_EQ(q.queues[s].subMesh, s);
    EXPECT_EQ(std::vector<uint32_t>(q.queueIds.begin() + q.queues[s].first,
                                    q.queueIds.begin() + q.queues[s].first + q.queues[s].count),
              ids);
  }
}
