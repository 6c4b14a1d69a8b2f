// crowdbake inspect, verify and export: what a pack holds, whether it is sound, and its images.
// All three work chunk by chunk from the chunk registry (crowd/formats/registry.h), so a new
// chunk type shows up in them through its codec alone.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "commands.h"
#include "crowd/bake/preview.h"
#include "crowd/formats/chunks.h"
#include "crowd/formats/error.h"
#include "crowd/formats/registry.h"
#include "crowd/runtime/images.h"

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
const char *const kExportHelp = R"(Writes every image a chunk holds through OpenImageIO: float
textures as OpenEXR (animation.exr, skin.exr), 8- and 16-bit ones as PNG (diffuse.png, per
impostor and frame its normals, UVs and regions); and, for a pack with a skeleton, preview.png:
the mesh skinned from the animation texture a quarter of the way into the first clip, seen from
the front, one tint per sub-mesh.)";

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

void writeImage(const std::string &path, const pack::Image &image) {
  images::write(path, image);
  std::cout << path << "\n";
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

int cmdExport(int argc, char **argv) {
  std::string path, dir;
  CLI::App app(kExportHelp, "crowdbake export");
  example(app, "crowdbake export humanoid.crowdpack --images textures/");
  addPack(app, path);
  app.add_option("--images", dir, "folder to write the images into")->required();
  if (!parseArgs(app, argc, argv))
    return 0;
  auto reader = pack::Reader::open(path);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec)
    throw Error(dir + ": cannot create directory: " + ec.message());
  using Pixel = pack::Image::Pixel;
  for (size_t i = 0; i < reader.chunks().size(); ++i) {
    const auto &c = reader.chunks()[i];
    const std::string ctx = pack::chunkContext(reader, i);
    const pack::ChunkCodec &codec = pack::codecOf(c, ctx);
    if (!codec.images)
      continue;
    for (const auto &image : codec.images(reader.payload(c), c.version, ctx)) {
      const bool isFloat = image.pixel == Pixel::F16 || image.pixel == Pixel::F32;
      writeImage(dir + "/" + image.name + (isFloat ? ".exr" : ".png"), image);
    }
  }
  if (reader.find(pack::kSkeleton)) {
    const auto p = pack::loadAnimationPack(reader);
    const uint32_t size = 512;
    pack::Image preview{"preview", size,
                        size,      3,
                        Pixel::U8, renderPreview(p, 0, p.clips[0].frameCount / 4, int(size))};
    writeImage(dir + "/preview.png", preview);
  }
  return 0;
}

} // namespace crowd::cli
