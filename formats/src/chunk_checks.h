// What the chunk codecs of chunks.h share: texture sizes and finite floats, checked as a
// decoder reads them, and the bounds they read arrays under.
#pragma once
#include <cmath>
#include <string>
#include <vector>

#include "crowd/formats/bytes.h"
#include "crowd/formats/limits.h"

namespace crowd::pack::checks {

inline constexpr uint32_t kMaxTextureSide = limits::kTextureSide;
inline constexpr uint64_t kMaxElements = limits::kChunkElements;

// Texture width and height, each in 1..maxSide.
inline void readSize(ByteReader &r, uint32_t &width, uint32_t &height, uint32_t maxSide) {
  width = r.get<uint32_t>("width");
  height = r.get<uint32_t>("height");
  if (width == 0 || height == 0 || width > maxSide || height > maxSide)
    r.fail("width/height", std::to_string(width) + "x" + std::to_string(height) +
                               " is out of range 1.." + std::to_string(maxSide));
}

inline void checkFinite(ByteReader &r, const std::vector<float> &v, const char *field) {
  for (size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      r.fail(field, "value " + std::to_string(i) + " is not finite");
}

} // namespace crowd::pack::checks
