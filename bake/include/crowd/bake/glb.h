// The GLB container of glTF 2.0: a 12-byte header, the JSON chunk (padded with spaces) and a
// binary chunk (padded with zeros), each 4-aligned. One writer and one reader for every tool that
// makes or edits a .glb (export, pose, the meshopt decode, the tests' writers).
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace crowd {

// `gltf` and `bin` as a .glb; `bin` empty writes no binary chunk.
std::vector<uint8_t> glbBytes(const nlohmann::json &gltf, const std::vector<uint8_t> &bin);

struct GlbParts {
  std::string json;         // the JSON chunk's text (the whole file when it is not a GLB)
  std::vector<uint8_t> bin; // the binary chunk's bytes
  bool hasBin = false;
};

// The parts of `bytes`: a GLB's two chunks, or a .gltf's text whole. A chunk that runs past the
// file is an error naming `path`.
GlbParts glbParts(const std::vector<uint8_t> &bytes, const std::string &path);

} // namespace crowd
