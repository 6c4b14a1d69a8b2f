// Fuzzes the point-cache reader (PC2 and MDD cloth caches): any bytes, as a .pc2 and as a .mdd,
// must open and read every frame or give a crowd::Error, never a crash, UB, a hang or an
// allocation past the header's checked counts. The reader streams from a file, so each input
// is written to a private folder first.
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "crowd/support/point_cache.h"
#include "crowd/formats/error.h"
#include "fuzz_folder.h"

namespace {

std::string folder() {
  static const std::string dir = [] {
    std::string pattern = crowd::fuzz::makeFolder("cache");
    return pattern;
  }();
  return dir;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  for (const char *name : {"/input.pc2", "/input.mdd"}) {
    const std::string path = folder() + name;
    std::ofstream(path, std::ios::binary | std::ios::trunc)
        .write(reinterpret_cast<const char *>(data), std::streamsize(size));
    try {
      crowd::PointCacheReader reader(path);
      std::vector<glm::vec3> frame;
      for (uint32_t f = 0; f < reader.info().frameCount && f < 64; ++f)
        reader.readFrame(f, frame);
    } catch (const crowd::Error &) {
    }
  }
  return 0;
}
