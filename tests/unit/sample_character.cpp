#include "sample_character.h"

#include "crowd/bake/import.h"
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

} // namespace crowd::test
