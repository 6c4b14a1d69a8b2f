#include "sample_character.h"

#include "crowd/bake/anim_bake.h"
#include "crowd/bake/import.h"
#include "crowd/bake/lod_bake.h"
#include "crowd/samples/samples.h"
#include "gltf_writer.h"

namespace crowd::test {

namespace {
const std::string &samplesDir() {
  static const std::string dir = [] {
    std::string d = tempDir("samples");
    samples::writeSamples(d);
    return d;
  }();
  return dir;
}

Character importSample(const std::string &file) {
  Reporter r;
  r.quiet = true;
  return importGltf(samplesDir() + "/" + file, {}, r);
}
} // namespace

const Character &sampleHumanoid() {
  static const Character c = importSample("humanoid.glb");
  return c;
}

std::vector<OutfitInput> sampleOutfits() {
  return {{"dress", importSample("outfit_dress.glb"), {}},
          {"jumper_skirt", importSample("outfit_jumper_skirt.glb"), {}},
          {"shirt_trousers", importSample("outfit_shirt_trousers.glb"), {}}};
}

const pack::AnimationPack &sampleHumanoidLodPack() {
  static const pack::AnimationPack p = [] {
    Character c = sampleHumanoid();
    Reporter rep;
    rep.quiet = true;
    pack::Lod lod = applyLod(c, {}, rep);
    AnimBakeResult res = bakeAnimation(c, {}, rep);
    res.pack.lod = lod;
    return pack::loadAnimationPack(pack::Reader(pack::packBytes(res.pack), "mem"));
  }();
  return p;
}

} // namespace crowd::test
