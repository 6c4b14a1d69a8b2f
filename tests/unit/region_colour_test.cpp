#include <gtest/gtest.h>

#include "crowd/bake/anim_bake.h"
#include "crowd/bake/import.h"
#include "crowd/formats/error.h"
#include "crowd/runtime/region_colour.h"

using namespace crowd;

namespace {

// The Blender trooper: a textured uniform, a green helmet and a black rifle without texture.
pack::AnimationPack trooper() {
  Reporter r;
  r.quiet = true;
  const Character c =
      importGltf(std::string(CROWD_SOURCE_DIR) + "/tests/data/blender/trooper_cm.glb", {}, r);
  return bakeAnimation(c, {}, r).pack;
}

size_t subMesh(const pack::AnimationPack &p, const std::string &name) {
  for (size_t s = 0; s < p.mesh.subMeshes.size(); ++s)
    if (p.mesh.subMeshes[s].name == name)
      return s;
  ADD_FAILURE() << "no sub-mesh " << name;
  return 0;
}

// Each sub-mesh keeps its material's base colour and says whether the diffuse texture applies;
// the pack round-trips them, and the player draws them where the scene's palette is silent.
TEST(Looks, EachSubMeshKeepsItsMaterialsColourAndTexture) {
  const pack::AnimationPack baked = trooper();
  const auto p = pack::loadAnimationPack(pack::Reader(pack::packBytes(baked), "trooper"));
  ASSERT_TRUE(p.looks && p.diffuse);
  const size_t helmet = subMesh(p, "Helmet"), uniform = subMesh(p, "Uniform");
  const std::vector<std::pair<std::string, glm::vec3>> none;
  auto near = [](std::array<float, 4> a, std::array<float, 4> b) {
    for (int k = 0; k < 4; ++k)
      EXPECT_NEAR(a[size_t(k)], b[size_t(k)], 1e-6) << k;
  };
  near(runtime::regionColour(p, helmet, none), {0.2f, 0.3f, 0.2f, 0});
  near(runtime::regionColour(p, uniform, none), {1, 1, 1, 1});
  // A palette entry by name, then "default" for the rest; the texture flag stays the material's.
  const std::vector<std::pair<std::string, glm::vec3>> palette = {{"default", {0.5f, 0.4f, 0.3f}},
                                                                  {"Helmet", {0.9f, 0.1f, 0.1f}}};
  near(runtime::regionColour(p, helmet, palette), {0.9f, 0.1f, 0.1f, 0});
  near(runtime::regionColour(p, uniform, palette), {0.5f, 0.4f, 0.3f, 1});
  // A pack from before looks were stored: light grey, textured.
  pack::AnimationPack old = p;
  old.looks.reset();
  near(runtime::regionColour(old, helmet, none), {0.8f, 0.8f, 0.8f, 1});
}

TEST(Looks, DamagedLooksAreAClearError) {
  pack::AnimationPack p = trooper();
  auto expectError = [&](const char *what) {
    try {
      pack::loadAnimationPack(pack::Reader(pack::packBytes(p), "damaged"));
      ADD_FAILURE() << "no error for " << what;
    } catch (const Error &e) {
      EXPECT_NE(std::string(e.what()).find("chunk LOOK"), std::string::npos) << e.what();
    }
  };
  p.looks->colours[1] = 2.0f;
  expectError("a colour past 1");
  p.looks->colours[1] = 0.5f;
  p.looks->textured.push_back(0);
  p.looks->colours.insert(p.looks->colours.end(), {0, 0, 0, 1});
  expectError("one look too many");
  p.looks->textured.pop_back();
  p.looks->colours.resize(p.looks->colours.size() - 4);
  p.looks->textured[0] = 7;
  expectError("a texture flag that is not 0 or 1");
}

} // namespace
