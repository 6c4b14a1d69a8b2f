// Reading a whole file that anyone may have named: the bake's inputs, the player's packs, scenes
// and world images. The file is checked to be a regular file (a folder, FIFO or device such as
// /dev/zero would fail late or read forever) within a byte bound before a byte is read, and
// then exactly its size is read. Errors name the file (as `label`, or the path) and say why.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "crowd/formats/limits.h"

namespace crowd {

// What a file over its bound is told, after the figures: how to raise the bound, or nothing.
struct FileBound {
  uint64_t maxBytes = limits::kInputFileBytes;
  std::string raise; // e.g. "--max-file-size raises it"
};

// The size of `path` after the checks above.
uint64_t checkRegularFile(const std::string &path, const FileBound &bound,
                          const std::string &label = "");
// The whole of `path`, after the checks above.
std::vector<uint8_t> readRegularFile(const std::string &path, const FileBound &bound,
                                     const std::string &label = "");

} // namespace crowd
