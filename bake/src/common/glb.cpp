#include "crowd/bake/glb.h"

#include "crowd/formats/error.h"

#include <cstring>

namespace crowd {

std::vector<uint8_t> glbBytes(const nlohmann::json &gltf, const std::vector<uint8_t> &bin) {
  std::string text = gltf.dump();
  text.resize((text.size() + 3) / 4 * 4, ' ');
  const uint64_t binLength = (bin.size() + 3) / 4 * 4;
  std::vector<uint8_t> out;
  out.reserve(28 + text.size() + binLength);
  auto u32 = [&](uint64_t v) {
    for (int k = 0; k < 4; ++k)
      out.push_back(uint8_t(v >> (8 * k)));
  };
  u32(0x46546C67); // "glTF"
  u32(2);
  u32(12 + 8 + text.size() + (bin.empty() ? 0 : 8 + binLength));
  u32(text.size());
  u32(0x4E4F534A); // "JSON"
  out.insert(out.end(), text.begin(), text.end());
  if (!bin.empty()) {
    u32(binLength);
    u32(0x004E4942); // "BIN\0"
    out.insert(out.end(), bin.begin(), bin.end());
    out.resize(out.size() + (binLength - bin.size()), 0);
  }
  return out;
}

GlbParts glbParts(const std::vector<uint8_t> &bytes, const std::string &path) {
  GlbParts parts;
  if (bytes.size() < 4 || std::memcmp(bytes.data(), "glTF", 4) != 0) {
    parts.json.assign(bytes.begin(), bytes.end());
    return parts;
  }
  auto u32 = [&](size_t at) {
    uint32_t v = 0;
    if (at + 4 <= bytes.size())
      std::memcpy(&v, bytes.data() + at, 4);
    return v;
  };
  const uint64_t jsonLength = u32(12);
  if (bytes.size() < 20 || 20 + jsonLength > bytes.size())
    throw Error(path + ": the GLB's JSON chunk runs past the file");
  parts.json.assign(bytes.begin() + 20, bytes.begin() + long(20 + jsonLength));
  const uint64_t binAt = 20 + jsonLength;
  if (binAt + 8 <= bytes.size() && u32(binAt + 4) == 0x004E4942) { // "BIN\0"
    const uint64_t binLength = u32(binAt);
    if (binAt + 8 + binLength > bytes.size())
      throw Error(path + ": the GLB's binary chunk runs past the file");
    parts.bin.assign(bytes.begin() + long(binAt + 8), bytes.begin() + long(binAt + 8 + binLength));
    parts.hasBin = true;
  }
  return parts;
}

} // namespace crowd
