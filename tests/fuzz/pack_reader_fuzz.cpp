// Fuzzes the pack reader (animation, impostor and character packs) and the chunk registry's
// codecs (inspect, export): any bytes must give a pack or a crowd::Error, never a crash or UB.
// Each input is read twice: as it is, and with its checksums and file size repaired, so the
// mutations also reach the chunk decoders behind the CRC checks.
#include <cstdint>
#include <cstring>
#include <vector>

#include "crowd/formats/character_pack.h"
#include "crowd/formats/chunks.h"
#include "crowd/formats/error.h"
#include "crowd/formats/impostor.h"
#include "crowd/formats/registry.h"

using namespace crowd::pack;

namespace {

// Every chunk through its codec (inspect, export), then the whole pack (the player, verify).
void readAll(std::vector<uint8_t> bytes) {
  try {
    Reader r(std::move(bytes), "fuzz");
    for (size_t i = 0; i < r.chunks().size(); ++i) {
      const ChunkEntry &c = r.chunks()[i];
      try {
        const ChunkCodec &codec = codecOf(c, chunkContext(r, i));
        codec.describe(r.payload(c), c.version, "fuzz");
        if (codec.images)
          codec.images(r.payload(c), c.version, "fuzz");
      } catch (const crowd::Error &) {
      }
    }
    if (r.find(kImpostor) && !r.find(kSkeleton))
      loadImpostorPack(r);
    else
      loadCharacterPack(r); // an animation pack, with or without impostor chunks
  } catch (const crowd::Error &) {
  }
}

void put32(std::vector<uint8_t> &b, size_t at, uint32_t v) { std::memcpy(&b[at], &v, 4); }

std::vector<uint8_t> repaired(std::vector<uint8_t> b) {
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
      put32(b, e + 24, crc32(std::span<const uint8_t>(b).subspan(offset, length)));
  }
  put32(b, 24, crc32(std::span<const uint8_t>(b).subspan(kHeaderSize, count * kTableEntrySize)));
  return b;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  std::vector<uint8_t> bytes(data, data + size);
  readAll(bytes);
  readAll(repaired(std::move(bytes)));
  return 0;
}
