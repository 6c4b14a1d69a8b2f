// Real glTF characters, written by real exporters: ../shared/assets/gltf's (when that folder is
// beside the checkout), the Blender exports in tests/data/blender and gltfpack's quantized copies
// of two of them in tests/data/gltfpack (always: they are committed). Without the shared folder
// the tests use the other two and say so (a "SKIP:" line, which ./run lists after ctest); where
// CROWD_REQUIRE=all (CI) its absence is an error.
#pragma once
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "skip.h"

namespace crowd::test {

inline std::vector<std::string> realModels() {
  std::vector<std::string> files;
  for (const std::string &dir :
       {std::string(CROWD_SHARED_ASSETS), std::string(CROWD_SOURCE_DIR) + "/tests/data/blender",
        std::string(CROWD_SOURCE_DIR) + "/tests/data/gltfpack"}) {
    if (!std::filesystem::exists(dir)) {
      if (requireAll())
        throw std::runtime_error("CROWD_REQUIRE=all, but the shared models are absent: " + dir);
      std::printf("SKIP: the models of %s are absent: this test ran on the others only\n",
                  dir.c_str());
      continue;
    }
    for (const auto &e : std::filesystem::recursive_directory_iterator(dir))
      if (e.path().extension() == ".glb" || e.path().extension() == ".gltf")
        files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

} // namespace crowd::test
