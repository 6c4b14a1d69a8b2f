#include "crowd/formats/container.h"

#include <array>
#include <atomic>
#include <bit>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <mutex>
#include <set>
#include <unistd.h>

#include "crowd/formats/bytes.h"
#include "crowd/formats/error.h"
#include "crowd/formats/file_read.h"

namespace crowd::pack {

static_assert(std::endian::native == std::endian::little,
              "packs are little-endian; port ByteWriter");

std::string fourccName(uint32_t type) {
  std::string s;
  for (int i = 0; i < 4; ++i) {
    char c = char((type >> (8 * i)) & 0xff);
    s += (c >= 32 && c < 127) ? c : '?';
  }
  return s;
}

// CRC-32 (IEEE, reflected): the standard library has none and formats/ depends on nothing else.
uint32_t crc32(std::span<const uint8_t> bytes) {
  static const auto table = [] {
    std::array<uint32_t, 256> t{};
    for (uint32_t i = 0; i < 256; ++i) {
      uint32_t c = i;
      for (int k = 0; k < 8; ++k)
        c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  uint32_t c = 0xFFFFFFFFu;
  for (uint8_t b : bytes)
    c = table[(c ^ b) & 0xff] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

static size_t alignUp(size_t v) { return (v + kAlignment - 1) / kAlignment * kAlignment; }

void Writer::add(uint32_t type, uint32_t version, std::vector<uint8_t> payload) {
  chunks_.push_back({type, version, std::move(payload)});
}

std::vector<uint8_t> Writer::bytes() const {
  ByteWriter table;
  size_t offset = alignUp(kHeaderSize + kTableEntrySize * chunks_.size());
  std::vector<size_t> offsets;
  for (const auto &c : chunks_) {
    offsets.push_back(offset);
    table.put<uint32_t>(c.type);
    table.put<uint32_t>(c.version);
    table.put<uint64_t>(offset);
    table.put<uint64_t>(c.payload.size());
    table.put<uint32_t>(crc32(c.payload));
    table.put<uint32_t>(0);
    offset = alignUp(offset + c.payload.size());
  }
  std::vector<uint8_t> tableBytes = table.take();
  ByteWriter header;
  for (char m : kMagic)
    header.put<char>(m);
  header.put<uint32_t>(kContainerVersion);
  header.put<uint32_t>(uint32_t(chunks_.size()));
  header.put<uint64_t>(offset);
  header.put<uint32_t>(crc32(tableBytes));
  header.put<uint32_t>(0);
  std::vector<uint8_t> out = header.take();
  out.insert(out.end(), tableBytes.begin(), tableBytes.end());
  out.resize(offset, 0);
  for (size_t i = 0; i < chunks_.size(); ++i)
    if (!chunks_[i].payload.empty())
      std::memcpy(out.data() + offsets[i], chunks_[i].payload.data(), chunks_[i].payload.size());
  return out;
}

namespace {
// Temporary files being written, so abandonPendingWrites can remove them.
std::mutex pendingMutex;
std::set<std::string> pendingWrites;
} // namespace

void abandonPendingWrites() {
  pendingMutex.lock(); // never unlocked: the process is ending
  for (const auto &tmp : pendingWrites)
    std::remove(tmp.c_str());
}

void writeFileAtomic(const std::string &path, std::span<const uint8_t> data) {
  // Unique per process and per call: threads (and farm workers) may write the same path at once.
  static std::atomic<uint64_t> serial{0};
  std::string tmp =
      path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(serial.fetch_add(1));
  {
    std::lock_guard<std::mutex> lock(pendingMutex);
    pendingWrites.insert(tmp);
  }
  auto done = [&] {
    std::lock_guard<std::mutex> lock(pendingMutex);
    pendingWrites.erase(tmp);
  };
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) {
      done();
      throw Error(path + ": cannot create temporary file " + tmp);
    }
    f.write(reinterpret_cast<const char *>(data.data()), std::streamsize(data.size()));
    f.close();
    if (!f) {
      std::remove(tmp.c_str());
      done();
      throw Error(path + ": write failed (disk full?)");
    }
  }
  const bool renamed = std::rename(tmp.c_str(), path.c_str()) == 0;
  if (!renamed)
    std::remove(tmp.c_str());
  done();
  if (!renamed)
    throw Error(path + ": cannot rename temporary file into place");
}

Reader::Reader(std::vector<uint8_t> bytes, std::string name)
    : bytes_(std::move(bytes)), name_(std::move(name)) {
  const std::string ctx = "pack '" + name_ + "'";
  if (bytes_.size() < kHeaderSize)
    throw Error(ctx + ": truncated: " + std::to_string(bytes_.size()) +
                " bytes, smaller than the 32-byte header");
  if (std::memcmp(bytes_.data(), kMagic, 8) != 0)
    throw Error(ctx + ": bad magic: not a crowdpack file");
  ByteReader header{std::span<const uint8_t>(bytes_).subspan(8, kHeaderSize - 8), ctx + ", header"};
  version_ = header.get<uint32_t>("version");
  uint32_t count = header.get<uint32_t>("chunk count");
  uint64_t fileSize = header.get<uint64_t>("file size");
  uint32_t tableCrc = header.get<uint32_t>("table checksum");
  if (version_ != kContainerVersion)
    throw Error(ctx + ", header, field 'version': version " + std::to_string(version_) +
                " is not supported (this reader knows " + std::to_string(kContainerVersion) + ")");
  if (fileSize != bytes_.size())
    throw Error(ctx + ", header, field 'file size': says " + std::to_string(fileSize) +
                " bytes but the file has " + std::to_string(bytes_.size()) +
                (fileSize > bytes_.size() ? " (truncated)" : ""));
  if (count > kMaxChunks)
    throw Error(ctx + ", header, field 'chunk count': " + std::to_string(count) + " is absurd");
  size_t tableSize = size_t(count) * kTableEntrySize;
  if (kHeaderSize + tableSize > bytes_.size())
    throw Error(ctx + ": chunk table runs past the end of the file");
  auto tableBytes = std::span(bytes_).subspan(kHeaderSize, tableSize);
  if (crc32(tableBytes) != tableCrc)
    throw Error(ctx + ", chunk table: checksum mismatch (file corrupted)");
  ByteReader table(tableBytes, ctx + ", chunk table");
  for (uint32_t i = 0; i < count; ++i) {
    ChunkEntry e;
    e.type = table.get<uint32_t>("type");
    e.version = table.get<uint32_t>("chunk version");
    e.offset = table.get<uint64_t>("offset");
    e.size = table.get<uint64_t>("size");
    e.crc = table.get<uint32_t>("checksum");
    table.get<uint32_t>("reserved");
    std::string cctx = ctx + ", chunk " + fourccName(e.type);
    if (e.offset % kAlignment != 0)
      throw Error(cctx + ", field 'offset': " + std::to_string(e.offset) + " is not aligned");
    if (e.offset < kHeaderSize + tableSize || e.offset > bytes_.size() ||
        e.size > bytes_.size() - e.offset)
      throw Error(cctx + ", field 'offset/size': [" + std::to_string(e.offset) + ", +" +
                  std::to_string(e.size) + ") lies outside the file");
    if (crc32(std::span(bytes_).subspan(e.offset, e.size)) != e.crc)
      throw Error(cctx + ": checksum mismatch (payload corrupted)");
    for (const auto &other : chunks_)
      if (other.type == e.type && !repeatable(e.type))
        throw Error(cctx + ": appears twice");
    chunks_.push_back(e);
  }
}

Reader Reader::open(const std::string &path) {
  // No byte bound but memory: a pack is as large as its bake made it (joint matrices of every
  // frame run to gigabytes); what it declares inside is bounded by the chunk checks.
  return Reader(readRegularFile(path, {UINT64_MAX, ""}, "pack '" + path + "'"), path);
}

const ChunkEntry *Reader::find(uint32_t type) const {
  for (const auto &c : chunks_)
    if (c.type == type)
      return &c;
  return nullptr;
}

const ChunkEntry &Reader::require(uint32_t type) const {
  const ChunkEntry *c = find(type);
  if (!c)
    throw Error("pack '" + name_ + "': required chunk " + fourccName(type) + " is missing");
  return *c;
}

std::span<const uint8_t> Reader::payload(const ChunkEntry &chunk) const {
  return std::span(bytes_).subspan(chunk.offset, chunk.size);
}

} // namespace crowd::pack
