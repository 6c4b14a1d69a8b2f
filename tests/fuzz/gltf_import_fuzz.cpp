// Fuzzes the glTF importer: any bytes, as a .gltf (JSON) or a .glb (by its magic), must give a
// Character or a crowd::Error, never a crash, UB, a hang or an allocation past the limits. The
// input is written to a private folder (the importer reads files, as the bakes do) beside one
// small external buffer, so URIs that name "buffer.bin" reach the external-buffer path too.
#include <cstdint>
#include <fstream>
#include <string>

#include "crowd/bake/import.h"
#include "crowd/bake/report.h"
#include "crowd/formats/error.h"
#include "fuzz_folder.h"

namespace {

std::string folder() {
  static const std::string dir = [] {
    std::string pattern = crowd::fuzz::makeFolder("gltf");
    std::ofstream(pattern + "/buffer.bin", std::ios::binary) << std::string(256, '\x01');
    return pattern;
  }();
  return dir;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const bool glb = size >= 4 && std::string(reinterpret_cast<const char *>(data), 4) == "glTF";
  const std::string path = folder() + (glb ? "/input.glb" : "/input.gltf");
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char *>(data), std::streamsize(size));
  crowd::Reporter reporter;
  reporter.quiet = true;
  try {
    crowd::importGltf(path, crowd::ImportOptions{}, reporter);
  } catch (const crowd::Error &) {
  }
  return 0;
}
