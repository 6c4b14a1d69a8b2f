// The chunk registry: every chunk type a pack may hold, registered once with its four
// characters, the chunk versions this build reads and writes, a decoder that describes the chunk
// (inspect) and the images it holds (export). `crowdbake inspect`, `verify` and `export` work
// from this table, not from pack kinds; a new chunk is one codec and one line in registry.cpp.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "crowd/formats/container.h"

namespace crowd::pack {

// One value of a description: its text, and whether that text is a JSON literal (a number, true
// or false), which JSON writes bare.
struct Value {
  std::string text;
  bool literal = false;
};
Value text(std::string s);
Value number(double v);

// What a chunk holds, for people and for JSON: fields (key: value) and tables (a row per joint,
// clip, sub-mesh, ...).
struct Description {
  struct Field {
    std::string key;
    Value value;
  };
  struct Table {
    std::string name;
    std::vector<std::string> columns;
    std::vector<std::vector<Value>> rows;
  };
  std::vector<Field> fields;
  std::vector<Table> tables;
  Description &add(std::string key, Value v) {
    fields.push_back({std::move(key), std::move(v)});
    return *this;
  }
};

// An image a chunk holds (a texture, an atlas frame), ready to be written as a file.
struct Image {
  enum class Pixel { U8, U16, F16, F32 };
  std::string name; // file name without extension, unique within the pack
  uint32_t width = 0, height = 0, channels = 0;
  Pixel pixel = Pixel::U8;
  std::vector<uint8_t> bytes; // width * height * channels pixels, rows from the top
};

struct ChunkCodec {
  uint32_t type = 0;
  const char *title = "";     // "animation texture"
  uint32_t oldestVersion = 1; // the oldest chunk version this build reads
  uint32_t version = 1;       // the version it writes (and the newest it reads)
  // Decodes the payload (every check local to the chunk; throws crowd::Error with `context`).
  Description (*describe)(std::span<const uint8_t>, uint32_t version, const std::string &context);
  // The chunk's images, decoded; null when the chunk holds none.
  std::vector<Image> (*images)(std::span<const uint8_t>, uint32_t version,
                               const std::string &context) = nullptr;
};

const std::vector<ChunkCodec> &chunkCodecs();
// Adds a chunk type to the registry (a plug-in's, or a test's), before any pack is read on another
// thread: inspect, verify, export's images and diff then handle it through its codec alone.
// Throws crowd::Error for a type already registered or a codec without describe.
void registerChunkCodec(const ChunkCodec &codec);
// What this build reads and writes, for --version: the container version and, per chunk type,
// the versions it reads and the one it writes ("SKEL 1 (writes 1)", "IMPO 1-4 (writes 4)").
std::string formatVersions();
// The codec of a chunk type, or null when this build does not know it.
const ChunkCodec *findCodec(uint32_t type);
// The codec of a chunk, after checking its version is one the codec reads; throws with `context`.
const ChunkCodec &codecOf(const ChunkEntry &chunk, const std::string &context);

// "pack 'NAME', chunk SKEL" or, for a repeatable type, "... chunk IMPO #2": how errors name it.
std::string chunkContext(const Reader &reader, size_t chunkIndex);

// Verifies a pack beyond its container: every chunk is of a known type and version and decodes,
// and the chunks agree with each other (a character pack's cross-references, or an impostor
// pack's). Returns one line saying what the pack holds; throws crowd::Error on the first problem.
std::string verifyPack(const Reader &reader);

} // namespace crowd::pack
