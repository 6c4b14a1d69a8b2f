// glTF files with meshopt-compressed buffer views (EXT_meshopt_compression as gltfpack -c writes
// it, KHR_meshopt_compression as -cc names it), made here with meshoptimizer's encoders from the
// sample humanoid: they import as the uncompressed file does; and the failure modes, each a clear
// error naming the view: sizes that lie, an unknown filter or mode, a codec version the linked
// meshoptimizer cannot decode, compressed bytes outside their buffer. tests/scripts/gltfpack.sh
// checks gltfpack's own files.
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>

#include <gtest/gtest.h>
#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

#include "crowd/bake/glb.h"
#include "crowd/bake/import.h"
#include "crowd/formats/error.h"
#include "crowd/samples/samples.h"
#include "gltf_writer.h"
#include "skip.h"

using namespace crowd;
using nlohmann::json;

namespace {

struct Glb {
  json gltf;
  std::vector<uint8_t> bin;
};

Glb readGlb(const std::string &path) {
  std::ifstream f(path, std::ios::binary);
  GlbParts parts = glbParts(std::vector<uint8_t>((std::istreambuf_iterator<char>(f)), {}), path);
  return {json::parse(parts.json), std::move(parts.bin)};
}

void writeGlb(const std::string &path, const Glb &g) {
  const std::vector<uint8_t> bytes = glbBytes(g.gltf, g.bin);
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char *>(bytes.data()), std::streamsize(bytes.size()));
}

// The sample humanoid with every buffer view meshopt can take compressed as gltfpack compresses
// them: index views as TRIANGLES, the others as ATTRIBUTES of their stride (a multiple of 4),
// into the binary chunk, each view moved onto a fallback buffer without data. `edit` then
// changes the JSON, to make it lie.
const std::string &plainHumanoid() {
  static const std::string path = [] {
    const std::string dir = test::tempDir("meshopt_samples");
    samples::writeSamples(dir);
    return dir + "/humanoid.glb";
  }();
  return path;
}

std::string compressed(const std::string &dir, const char *extension,
                       const std::function<void(json &)> &edit = {}) {
  Glb g = readGlb(plainHumanoid());
  std::vector<int> indexViews, strides(g.gltf["bufferViews"].size(), 0);
  for (const auto &mesh : g.gltf["meshes"])
    for (const auto &p : mesh["primitives"])
      if (p.contains("indices"))
        indexViews.push_back(g.gltf["accessors"][p["indices"].get<size_t>()]["bufferView"]);
  for (const auto &a : g.gltf["accessors"]) {
    const int size = a["componentType"] == 5126 || a["componentType"] == 5125   ? 4
                     : a["componentType"] == 5123 || a["componentType"] == 5122 ? 2
                                                                                : 1;
    const std::map<std::string, int> width = {
        {"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4}, {"MAT4", 16}};
    if (a.contains("bufferView") && width.count(a["type"]))
      strides[a["bufferView"].get<size_t>()] = size * width.at(a["type"]);
  }
  const size_t total = g.bin.size();
  for (size_t v = 0; v < g.gltf["bufferViews"].size(); ++v) {
    json &view = g.gltf["bufferViews"][v];
    const size_t offset = view.value("byteOffset", 0), length = view["byteLength"];
    const bool index = std::count(indexViews.begin(), indexViews.end(), int(v)) > 0;
    const int stride = view.value("byteStride", strides[v]);
    std::vector<uint8_t> out;
    size_t count = 0;
    if (index && stride == 4 && length % 12 == 0) {
      count = length / 4;
      out.resize(meshopt_encodeIndexBufferBound(count, total));
      out.resize(meshopt_encodeIndexBuffer(
          out.data(), out.size(), reinterpret_cast<const uint32_t *>(&g.bin[offset]), count));
    } else if (!index && stride > 0 && stride % 4 == 0 && length % size_t(stride) == 0) {
      count = length / size_t(stride);
      out.resize(meshopt_encodeVertexBufferBound(count, size_t(stride)));
      out.resize(meshopt_encodeVertexBuffer(out.data(), out.size(), &g.bin[offset], count,
                                            size_t(stride)));
    } else {
      continue; // an image, or a view meshopt does not take
    }
    g.bin.resize((g.bin.size() + 3) / 4 * 4, 0);
    view["extensions"][extension] = {{"buffer", 0},
                                     {"byteOffset", g.bin.size()},
                                     {"byteLength", out.size()},
                                     {"byteStride", stride},
                                     {"count", count},
                                     {"mode", index ? "TRIANGLES" : "ATTRIBUTES"}};
    view["buffer"] = 1;
    g.bin.insert(g.bin.end(), out.begin(), out.end());
  }
  g.gltf["buffers"][0]["byteLength"] = g.bin.size();
  g.gltf["buffers"].push_back(
      {{"byteLength", total}, {"extensions", {{extension, {{"fallback", true}}}}}});
  g.gltf["extensionsUsed"].push_back(extension);
  g.gltf["extensionsRequired"].push_back(extension);
  if (edit)
    edit(g.gltf);
  const std::string path = dir + "/compressed.glb";
  writeGlb(path, g);
  return path;
}

std::string importError(const std::string &path) {
  Reporter r;
  r.quiet = true;
  try {
    importGltf(path, {}, r);
  } catch (const Error &e) {
    return e.what();
  }
  return "no error";
}

// The first compressed view of a mode.
json &firstView(json &gltf, const char *extension, const char *mode) {
  for (auto &view : gltf["bufferViews"])
    if (view.contains("extensions") && view["extensions"][extension]["mode"] == mode)
      return view["extensions"][extension];
  throw std::runtime_error("no compressed view");
}

// Triangles each turned to start at their smallest index: meshopt's index codec keeps every
// triangle and its winding but may start it at another corner.
std::vector<uint32_t> rotated(std::vector<uint32_t> indices) {
  for (size_t t = 0; t + 2 < indices.size(); t += 3)
    while (indices[t] > indices[t + 1] || indices[t] > indices[t + 2])
      std::rotate(&indices[t], &indices[t + 1], &indices[t + 3]);
  return indices;
}

TEST(Meshopt, CompressedViewsImportAsTheUncompressedFile) {
  Reporter r;
  r.quiet = true;
  const std::string dir = test::tempDir("meshopt_same");
  const Character plain = importGltf(plainHumanoid(), {}, r);
  for (const char *extension : {"EXT_meshopt_compression", "KHR_meshopt_compression"}) {
    SCOPED_TRACE(extension);
    const Character c = importGltf(compressed(dir, extension), {}, r);
    EXPECT_EQ(c.mesh.positions, plain.mesh.positions);
    EXPECT_EQ(rotated(c.mesh.indices), rotated(plain.mesh.indices));
    EXPECT_EQ(c.mesh.joints, plain.mesh.joints);
    EXPECT_EQ(c.mesh.weights, plain.mesh.weights);
    ASSERT_EQ(c.clips.size(), plain.clips.size());
    for (size_t k = 0; k < c.clips.size(); ++k)
      EXPECT_EQ(c.clips[k].name, plain.clips[k].name);
  }
}

TEST(Meshopt, FilesThatLieAreClearErrors) {
  const std::string dir = test::tempDir("meshopt_lies");
  const char *ext = "EXT_meshopt_compression";
  struct Case {
    const char *expect;
    std::function<void(json &)> edit;
  };
  const Case cases[] = {
      {"does not decode", [&](json &g) { firstView(g, ext, "ATTRIBUTES")["count"] = 7; }},
      {"does not decode", [&](json &g) { firstView(g, ext, "TRIANGLES")["byteLength"] = 5; }},
      {"does not suit mode", [&](json &g) { firstView(g, ext, "ATTRIBUTES")["byteStride"] = 6; }},
      {"lie outside its buffer",
       [&](json &g) { firstView(g, ext, "ATTRIBUTES")["byteOffset"] = 1u << 30; }},
      {"filter 'SQUASH'", [&](json &g) { firstView(g, ext, "ATTRIBUTES")["filter"] = "SQUASH"; }},
      {"filter QUATERNION with byteStride 12",
       [&](json &g) {
         for (auto &view : g["bufferViews"])
           if (view.contains("extensions") && view["extensions"][ext]["byteStride"] == 12) {
             view["extensions"][ext]["filter"] = "QUATERNION";
             break;
           }
       }},
      {"unknown mode 'POINTS'",
       [&](json &g) { firstView(g, ext, "ATTRIBUTES")["mode"] = "POINTS"; }},
      {"not a meshopt TRIANGLES stream",
       [&](json &g) {
         json &view = firstView(g, ext, "ATTRIBUTES");
         view["mode"] = "TRIANGLES", view["byteStride"] = 4, view["count"] = 3;
       }},
      {"buffer 9 does not exist", [&](json &g) { firstView(g, ext, "ATTRIBUTES")["buffer"] = 9; }},
      {"count missing", [&](json &g) { firstView(g, ext, "ATTRIBUTES").erase("count"); }},
      // 16M elements of 256 bytes: refused before 4 GiB are allocated for them.
      {"take the decoded views over 1024 MiB",
       [&](json &g) {
         json &view = firstView(g, ext, "ATTRIBUTES");
         view["count"] = 1 << 24, view["byteStride"] = 256;
       }},
  };
  for (const Case &c : cases) {
    const std::string message = importError(compressed(dir, ext, c.edit));
    EXPECT_NE(message.find(c.expect), std::string::npos) << c.expect << ": " << message;
    EXPECT_NE(message.find("bufferViews["), std::string::npos) << message;
  }
}

// A vertex stream's first byte holds its codec version: version 1 (meshoptimizer 0.23 on) is an
// error naming it where the linked library reads version 0 only.
TEST(Meshopt, ACodecVersionTheLinkedLibraryCannotDecodeIsNamed) {
  if (MESHOPTIMIZER_VERSION >= 230)
    CROWD_SKIP("the linked meshoptimizer decodes vertex codec version 1");
  const std::string dir = test::tempDir("meshopt_version");
  const std::string path = compressed(dir, "EXT_meshopt_compression");
  Glb g = readGlb(path);
  const json &view = firstView(g.gltf, "EXT_meshopt_compression", "ATTRIBUTES");
  g.bin[view["byteOffset"].get<size_t>()] = 0xA1;
  writeGlb(path, g);
  const std::string message = importError(path);
  EXPECT_NE(
      message.find("is of codec version 1, which the linked meshoptimizer 0.18 cannot decode"),
      std::string::npos)
      << message;
}

TEST(Meshopt, DracoAndKtx2StayClearErrors) {
  const std::string dir = test::tempDir("meshopt_draco");
  for (const char *extension : {"KHR_draco_mesh_compression", "KHR_texture_basisu"}) {
    test::GltfBuilder b;
    b.skinnedQuad();
    const std::string path = b.write(dir, "quad");
    json g = json::parse(std::ifstream(path));
    g["extensionsUsed"] = {extension};
    g["extensionsRequired"] = {extension};
    std::ofstream(path) << g.dump();
    const std::string message = importError(path);
    EXPECT_NE(message.find(std::string("unsupported required extension ") + extension),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("export"), std::string::npos) << message;
  }
}

} // namespace
