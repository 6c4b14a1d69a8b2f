// Keys that group vertices by exact values: a float goes in as its bit pattern, -0 as +0 (the
// two compare equal).
#pragma once
#include <cstdint>
#include <cstring>
#include <vector>

namespace crowd::lod {

inline void putBits(std::vector<uint32_t> &key, float f) {
  f += 0.0f; // -0 -> +0
  uint32_t b;
  std::memcpy(&b, &f, sizeof b);
  key.push_back(b);
}

} // namespace crowd::lod
