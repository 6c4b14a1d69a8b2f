// crowdbake export --gltf's file, read back as JSON: the skeleton, clips, primitives and
// vertices of what the player draws; and packs the exporter must handle without a crash: no
// clips, no LOD, morph targets, an unknown outfit. (tests/scripts/gltf_export.sh checks the
// files in the Khronos validator, three.js and Blender.)
#include <cstring>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "crowd/bake/gltf_export.h"
#include "crowd/formats/error.h"
#include "crowd/runtime/pose.h"
#include "sample_character.h"

using namespace crowd;
using nlohmann::json;

namespace {

json gltfJson(const std::vector<uint8_t> &glb) {
  EXPECT_GE(glb.size(), 20u);
  EXPECT_EQ(std::memcmp(glb.data(), "glTF", 4), 0);
  uint32_t length = 0;
  std::memcpy(&length, glb.data() + 12, 4);
  return json::parse(glb.begin() + 20, glb.begin() + 20 + length);
}

std::vector<uint8_t> exported(const pack::AnimationPack &p, GltfExportOptions o = {}) {
  Reporter r;
  r.quiet = true;
  return exportGltf(p, o, r);
}

TEST(GltfExport, TheCharacterAsThePlayerDrawsIt) {
  const pack::AnimationPack &p = test::sampleHumanoidLodPack();
  const json g = gltfJson(exported(p));
  EXPECT_EQ(g["skins"][0]["joints"].size(), p.skeleton.jointCount());
  ASSERT_EQ(g["animations"].size(), p.clips.size());
  for (size_t c = 0; c < p.clips.size(); ++c)
    EXPECT_EQ(g["animations"][c]["name"], p.clips[c].name);
  EXPECT_EQ(g["meshes"][0]["primitives"].size(), p.mesh.subMeshes.size());
  const auto full = runtime::poseMesh(p, {});
  const int position = g["meshes"][0]["primitives"][0]["attributes"]["POSITION"];
  EXPECT_EQ(g["accessors"][size_t(position)]["count"], full.vertices.size());
  // A LOD cut: fewer vertices, the same skeleton and clips.
  const uint32_t cut = (p.lod->floorVertices + uint32_t(p.mesh.vertexCount())) / 2;
  const json lod = gltfJson(exported(p, {"", cut}));
  const int lodPosition = lod["meshes"][0]["primitives"][0]["attributes"]["POSITION"];
  EXPECT_EQ(lod["accessors"][size_t(lodPosition)]["count"],
            runtime::poseMesh(p, {"", "", cut}).vertices.size());
  EXPECT_LT(lod["accessors"][size_t(lodPosition)]["count"], full.vertices.size());
  EXPECT_EQ(lod["animations"].size(), p.clips.size());
}

TEST(GltfExport, PacksWithoutClipsOrLodAndWithMorphTargets) {
  pack::AnimationPack still = test::sampleHumanoidLodPack();
  still.clips.clear();
  if (still.tracks)
    still.tracks->clips.clear();
  const json g = gltfJson(exported(still));
  EXPECT_FALSE(g.contains("animations")) << "a pack without clips has no animation";
  EXPECT_EQ(g["skins"][0]["joints"].size(), still.skeleton.jointCount());

  pack::AnimationPack noLod = test::sampleHumanoidLodPack();
  noLod.lod.reset();
  try {
    exported(noLod, {"", 100});
    ADD_FAILURE() << "a cut of a pack without LOD";
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("the pack has no LOD"), std::string::npos) << e.what();
  }
  try {
    exported(noLod, {"cape", 0});
    ADD_FAILURE() << "an outfit of a pack without outfits";
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("cape"), std::string::npos) << e.what();
  }

  pack::AnimationPack morphed = test::sampleHumanoidLodPack();
  pack::Morphs m;
  m.vertexCount = uint32_t(morphed.mesh.vertexCount());
  m.targets.push_back({"bulge", 0, 10, 0});
  m.offsets.assign(10 * 8, 0.5f);
  uint32_t frames = 0;
  for (const auto &c : morphed.clips)
    frames = std::max(frames, c.firstFrame + c.frameCount);
  m.slots.assign(size_t(frames) * pack::kMorphSlots, {});
  for (uint32_t f = 0; f < frames; ++f)
    m.slots[size_t(f) * pack::kMorphSlots] = {0, float(f % 2)};
  morphed.morphs = m;
  const json mg = gltfJson(exported(morphed));
  EXPECT_EQ(mg["meshes"][0]["primitives"][0]["targets"].size(), 1u);
  EXPECT_EQ(mg["meshes"][0]["extras"]["targetNames"][0], "bulge");
  for (const auto &a : mg["animations"]) {
    bool weights = false;
    for (const auto &channel : a["channels"])
      weights |= channel["target"]["path"] == "weights";
    EXPECT_TRUE(weights) << a["name"];
  }
}

} // namespace
