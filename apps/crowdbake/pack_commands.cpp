// crowdbake inspect and verify: what a pack holds and whether it is sound. Both work chunk by
// chunk from the chunk registry (crowd/formats/registry.h), so a new chunk type shows up in them
// through its codec alone (and in export's images, export_command.cpp).
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "commands.h"
#include "crowd/formats/chunks.h"
#include "crowd/formats/error.h"
#include "crowd/formats/registry.h"

using nlohmann::ordered_json;

namespace crowd::cli {

namespace {

const char *const kInspectHelp = R"(Lists the pack's chunks (type, version, offset, size, checksum)
and what each holds, decoded through its codec: provenance, joints, clips, texture sizes, mesh,
LOD, outfits, impostors. Each chunk is decoded on its own, so a pack whose chunks disagree with
each other can still be inspected (crowdbake verify says what disagrees).)";
const char *const kVerifyHelp = R"(Validates the container (magic, version, sizes, checksums),
decodes every chunk through its codec (an unknown type or version is an error) and checks the
chunks against each other. Exit code 0 when the pack is sound, 1 with the first problem
otherwise.)";
void addPack(CLI::App &app, std::string &pack) {
  app.add_option("PACK", pack, "a .crowdpack file")->required();
}

std::string hex32(uint32_t v) {
  char b[16];
  std::snprintf(b, sizeof b, "%08x", v);
  return b;
}

ordered_json toJson(const pack::Value &v) {
  return v.literal ? ordered_json::parse(v.text) : ordered_json(v.text);
}

ordered_json toJson(const pack::Description &d) {
  ordered_json j = ordered_json::object();
  for (const auto &f : d.fields)
    j[f.key] = toJson(f.value);
  for (const auto &t : d.tables) {
    ordered_json rows = ordered_json::array();
    for (const auto &row : t.rows) {
      ordered_json r;
      for (size_t c = 0; c < t.columns.size(); ++c)
        r[t.columns[c]] = toJson(row[c]);
      rows.push_back(r);
    }
    j[t.name] = rows;
  }
  return j;
}

void printText(std::ostream &o, const pack::Description &d) {
  for (const auto &f : d.fields)
    o << "    " << f.key << ": " << (f.value.text.empty() ? "-" : f.value.text) << "\n";
  for (const auto &t : d.tables) {
    o << "    " << t.name << " (" << t.rows.size() << "):";
    for (const auto &c : t.columns)
      o << " " << c;
    o << "\n";
    for (const auto &row : t.rows) {
      o << "     ";
      for (const auto &v : row)
        o << " " << (v.text.empty() ? "-" : v.text);
      o << "\n";
    }
  }
}

} // namespace

int cmdInspect(int argc, char **argv) {
  std::string path;
  bool asJson = false;
  CLI::App app(kInspectHelp, "crowdbake inspect");
  example(app, "crowdbake inspect humanoid.crowdpack --json");
  addPack(app, path);
  app.add_flag("--json", asJson, "print JSON instead of text");
  if (!parseArgs(app, argc, argv))
    return 0;
  auto reader = pack::Reader::open(path);
  const std::string file = std::filesystem::path(path).filename().string();
  ordered_json j;
  j["file"] = file;
  j["bytes"] = reader.fileSize();
  j["pack_checksum"] = hex32(pack::crc32(reader.fileBytes()));
  j["container_version"] = reader.version();
  std::ostringstream o;
  o << "pack " << file << ": " << reader.fileSize() << " bytes, container v" << reader.version()
    << ", crc32 " << j["pack_checksum"].get<std::string>() << "\n";
  for (size_t i = 0; i < reader.chunks().size(); ++i) {
    const auto &c = reader.chunks()[i];
    const std::string ctx = pack::chunkContext(reader, i);
    const pack::ChunkCodec &codec = pack::codecOf(c, ctx);
    const pack::Description d = codec.describe(reader.payload(c), c.version, ctx);
    j["chunks"].push_back({{"type", pack::fourccName(c.type)},
                           {"title", codec.title},
                           {"version", c.version},
                           {"offset", c.offset},
                           {"size", c.size},
                           {"crc32", hex32(c.crc)},
                           {"content", toJson(d)}});
    o << pack::fourccName(c.type) << " v" << c.version << " " << codec.title << ": " << c.size
      << " bytes at " << c.offset << ", crc32 " << hex32(c.crc) << "\n";
    printText(o, d);
  }
  std::cout << (asJson ? j.dump(2) + "\n" : o.str());
  return 0;
}

int cmdVerify(int argc, char **argv) {
  std::string path;
  CLI::App app(kVerifyHelp, "crowdbake verify");
  example(app, "crowdbake verify humanoid.crowdpack");
  addPack(app, path);
  if (!parseArgs(app, argc, argv))
    return 0;
  const std::string summary = pack::verifyPack(pack::Reader::open(path));
  std::cout << "ok: " << path << " (" << summary << ")\n";
  return 0;
}

} // namespace crowd::cli
