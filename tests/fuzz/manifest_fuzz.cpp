// Fuzzes the manifest reader (a character manifest or a library of them, as `crowdbake build`
// reads it): any bytes must load or give a crowd::Error, never a crash, UB, a hang or a read
// outside the manifest's folder. Each input is written to a private folder beside the files a
// manifest may name (a body, an outfit, a scene), so the parse reaches past the path checks.
#include <cstdint>
#include <fstream>
#include <string>

#include "crowd/bake/manifest.h"
#include "crowd/formats/error.h"
#include "fuzz_folder.h"

namespace {

std::string folder() {
  static const std::string dir = [] {
    std::string pattern = crowd::fuzz::makeFolder("manifest");
    for (const char *name : {"/body.glb", "/outfit.glb", "/cloth.pc2", "/village.glb"})
      std::ofstream(pattern + name) << "glTF";
    std::ofstream(pattern + "/scene.json") << R"({"packs": [{"path": "a.crowdpack"}]})";
    return pattern;
  }();
  return dir;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const std::string path = folder() + "/library.json";
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char *>(data), std::streamsize(size));
  try {
    crowd::Library library = crowd::loadLibrary(path);
    for (const auto &c : library.characters)
      (void)c.canonical().dump();
  } catch (const crowd::Error &) {
  }
  return 0;
}
