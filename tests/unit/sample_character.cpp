#include "sample_character.h"

#include "crowd/bake/anim_bake.h"
#include "crowd/bake/import.h"
#include "crowd/bake/lod_bake.h"
#include "crowd/samples/samples.h"
#include "gltf_writer.h"

namespace crowd::test {

const Character &sampleHumanoid() {
  static const Character c = [] {
    std::string dir = tempDir("samples");
    samples::writeSamples(dir);
    Reporter r;
    r.quiet = true;
    return importGltf(dir + "/humanoid.glb", {}, r);
  }();
  return c;
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
