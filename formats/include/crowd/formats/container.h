// The pack container: header, chunk table and aligned, checksummed payloads. Writing is
// deterministic and atomic; reading validates every offset, size and checksum before use.
//
// Layout (all integers little-endian):
//   header (32 bytes): magic "CRWDPACK", u32 version, u32 chunk count, u64 file size,
//                      u32 CRC-32 of the chunk table, u32 reserved (0)
//   chunk table: per chunk 32 bytes: u32 type (four characters), u32 chunk version,
//                u64 offset, u64 size, u32 CRC-32 of the payload, u32 reserved (0)
//   payloads, each starting at a multiple of kAlignment, zero padding between them.
#pragma once
#include "crowd/formats/limits.h"
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace crowd::pack {

inline constexpr char kMagic[8] = {'C', 'R', 'W', 'D', 'P', 'A', 'C', 'K'};
inline constexpr uint32_t kContainerVersion = 1;
inline constexpr size_t kAlignment = 64;
inline constexpr size_t kHeaderSize = 32;
inline constexpr size_t kTableEntrySize = 32;
inline constexpr uint32_t kMaxChunks = limits::kChunks;

// A chunk type is four ASCII characters read as a little-endian u32.
constexpr uint32_t fourcc(const char (&s)[5]) {
  return uint32_t(uint8_t(s[0])) | uint32_t(uint8_t(s[1])) << 8 | uint32_t(uint8_t(s[2])) << 16 |
         uint32_t(uint8_t(s[3])) << 24;
}
std::string fourccName(uint32_t type);
// Chunk types a pack may hold more than once (impostors: one per clip and outfit; cloth loops:
// one per outfit, garment and clip); every other
// type appears at most once.
constexpr bool repeatable(uint32_t type) {
  return type == fourcc("IMPO") || type == fourcc("CLTH");
}

uint32_t crc32(std::span<const uint8_t> bytes);

struct ChunkEntry {
  uint32_t type = 0;
  uint32_t version = 0;
  uint64_t offset = 0;
  uint64_t size = 0;
  uint32_t crc = 0;
};

// Writes to PATH.tmp-<pid> then renames over PATH: a failure never leaves a half file and
// never damages an earlier good one.
void writeFileAtomic(const std::string &path, std::span<const uint8_t> bytes);
// Removes every temporary file writeFileAtomic has open and blocks further writes: for a process
// about to end abruptly (a resource guard), so it leaves nothing half-written behind.
void abandonPendingWrites();

// Collects chunks in the order added and lays them out deterministically.
class Writer {
public:
  void add(uint32_t type, uint32_t version, std::vector<uint8_t> payload);
  std::vector<uint8_t> bytes() const;
  void writeAtomic(const std::string &path) const { writeFileAtomic(path, bytes()); }

private:
  struct Pending {
    uint32_t type, version;
    std::vector<uint8_t> payload;
  };
  std::vector<Pending> chunks_;
};

// An opened pack, fully validated at construction (header, table, bounds, checksums).
class Reader {
public:
  // `name` is used in error messages (usually the file path).
  Reader(std::vector<uint8_t> bytes, std::string name);
  static Reader open(const std::string &path);

  const std::string &name() const { return name_; }
  const std::vector<ChunkEntry> &chunks() const { return chunks_; }
  uint32_t version() const { return version_; }
  size_t fileSize() const { return bytes_.size(); }
  const std::vector<uint8_t> &fileBytes() const { return bytes_; }
  // Null when absent.
  const ChunkEntry *find(uint32_t type) const;
  // Throws when absent.
  const ChunkEntry &require(uint32_t type) const;
  std::span<const uint8_t> payload(const ChunkEntry &chunk) const;

private:
  std::vector<uint8_t> bytes_;
  std::string name_;
  uint32_t version_ = 0;
  std::vector<ChunkEntry> chunks_;
};

} // namespace crowd::pack
