// The pack fuzzers' repair: a pack's bytes with its file size and every checksum (chunks and
// table) recomputed, so that mutations also reach what lies behind the CRC checks.
#pragma once
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "crowd/formats/container.h"

namespace crowd::fuzz {

inline std::vector<uint8_t> repaired(std::vector<uint8_t> b) {
  using namespace crowd::pack;
  const auto put32 = [&](size_t at, uint32_t v) { std::memcpy(&b[at], &v, 4); };
  if (b.size() < kHeaderSize)
    return b;
  uint64_t size = b.size();
  std::memcpy(&b[16], &size, 8);
  uint32_t count;
  std::memcpy(&count, &b[12], 4);
  if (count > kMaxChunks || kHeaderSize + uint64_t(count) * kTableEntrySize > b.size())
    return b;
  for (uint32_t i = 0; i < count; ++i) {
    size_t e = kHeaderSize + i * kTableEntrySize;
    uint64_t offset, length;
    std::memcpy(&offset, &b[e + 8], 8);
    std::memcpy(&length, &b[e + 16], 8);
    if (offset <= b.size() && length <= b.size() - offset)
      put32(e + 24, crc32(std::span<const uint8_t>(b).subspan(offset, length)));
  }
  put32(24, crc32(std::span<const uint8_t>(b).subspan(kHeaderSize, count * kTableEntrySize)));
  return b;
}

} // namespace crowd::fuzz
