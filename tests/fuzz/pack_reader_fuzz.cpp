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
#include "pack_repair.h"

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

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  std::vector<uint8_t> bytes(data, data + size);
  readAll(bytes);
  readAll(crowd::fuzz::repaired(std::move(bytes)));
  return 0;
}
