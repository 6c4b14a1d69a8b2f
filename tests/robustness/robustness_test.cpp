// Malformed inputs through the real CLI: each must exit 1 with one line naming the problem.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sys/stat.h>

#include <gtest/gtest.h>

#include "../unit/cli_run.h"
#include "../unit/gltf_writer.h"
#include "crowd/formats/chunks.h"

using crowd::test::GltfBuilder;
namespace test = crowd::test;
namespace fs = std::filesystem;

namespace {

using test::CliRun;

CliRun crowdbake(const std::string &args) {
  return test::runCommand(std::string(CROWDBAKE) + " " + args);
}

void expectOneLineError(const CliRun &r, const std::string &needle) {
  test::expectOneLineError(r, "crowdbake", needle);
}

struct Case {
  const char *name;
  const char *expected;
  std::function<std::string(const std::string &dir)> make; // returns the input path
};

GltfBuilder quad() {
  GltfBuilder b;
  b.skinnedQuad();
  return b;
}

// Overwrites float `index` of accessor `acc` in the builder's binary buffer.
void poke(GltfBuilder &b, int acc, size_t index, float value) {
  size_t view = b.j["accessors"][size_t(acc)]["bufferView"];
  size_t offset = b.j["bufferViews"][view]["byteOffset"];
  std::memcpy(b.bin.data() + offset + index * 4, &value, 4);
}

const float kNaN = std::numeric_limits<float>::quiet_NaN();

// The quad as a .gltf whose buffer URI is `uri`, its real buffer as ext.bin beside it, and a
// copy of that buffer one folder up (where an escaping URI would find it).
std::string externalBufferAt(const std::string &d, const std::string &uri) {
  std::string p = quad().write(d, "ext", true);
  fs::copy_file(d + "/ext.bin", d + "/../outside.bin", fs::copy_options::overwrite_existing);
  nlohmann::json j = nlohmann::json::parse(std::ifstream(p));
  j["buffers"][0]["uri"] = uri;
  std::ofstream(p) << j.dump();
  return p;
}

// The same, its buffer URI naming `name`: a symbolic link to `target`.
std::string externalBufferThroughLink(const std::string &d, const std::string &name,
                                      const std::string &target) {
  fs::create_symlink(target, d + "/" + name);
  return externalBufferAt(d, name);
}

const std::vector<Case> kCases = {
    {"truncated_glb", "not a readable glTF",
     [](const std::string &d) {
       std::string p = quad().writeGlb(d, "t");
       fs::resize_file(p, fs::file_size(p) / 2);
       return p;
     }},
    {"bad_magic", "not a readable glTF",
     [](const std::string &d) {
       std::string p = quad().writeGlb(d, "m");
       std::fstream f(p, std::ios::in | std::ios::out | std::ios::binary);
       f.write("glTX", 4);
       return p;
     }},
    // Confinement: each refused before a byte of the named file is read.
    {"uri_traversal", "URI '../outside.bin': leaves the asset folder",
     [](const std::string &d) { return externalBufferAt(d, "../outside.bin"); }},
    {"uri_absolute", "URI '/etc/hostname': an absolute path is allowed only inside --asset-root",
     [](const std::string &d) { return externalBufferAt(d, "/etc/hostname"); }},
    {"uri_escaping_symlink", "URI 'link.bin': resolves through a link to",
     [](const std::string &d) {
       return externalBufferThroughLink(d, "link.bin", "../outside.bin");
     }},
    {"uri_dev_zero", "URI '/dev/zero': an absolute path is allowed only inside --asset-root",
     [](const std::string &d) { return externalBufferAt(d, "/dev/zero"); }},
    {"uri_symlink_to_dev_zero", "resolves through a link to /dev/zero",
     [](const std::string &d) { return externalBufferThroughLink(d, "zero.bin", "/dev/zero"); }},
    {"uri_fifo", "not a regular file (a FIFO): nothing read",
     [](const std::string &d) {
       mkfifo((d + "/fifo.bin").c_str(), 0600);
       return externalBufferAt(d, "fifo.bin");
     }},
    {"json_nested_100000", "JSON nests deeper than 64 levels",
     [](const std::string &d) {
       std::string p = d + "/deep.gltf";
       std::ofstream(p) << std::string(100000, '[') << std::string(100000, ']');
       return p;
     }},
    {"missing_buffer_file", "not a readable glTF",
     [](const std::string &d) {
       std::string p = quad().write(d, "ext", true);
       fs::remove(d + "/ext.bin");
       return p;
     }},
    {"accessor_out_of_range", "run past the end of bufferView",
     [](const std::string &d) {
       auto b = quad();
       b.j["accessors"][0]["count"] = 400;
       return b.write(d, "a");
     }},
    {"nan_position", "POSITION, accessor 0: element 1 is NaN",
     [](const std::string &d) {
       auto b = quad();
       poke(b, 0, 4, kNaN);
       return b.write(d, "n");
     }},
    {"nan_keyframe", "animation 'move', channel 0 output, accessor 6: element 1 is NaN",
     [](const std::string &d) {
       auto b = quad();
       b.animation("move", 1, "translation", {0, 1}, {0, 0.5f, 0, kNaN, 0, 0});
       return b.write(d, "k");
     }},
    {"joint_out_of_range", "uses joint 7 but the skin has 2",
     [](const std::string &d) {
       auto b = quad();
       size_t view = b.j["accessors"][1]["bufferView"];
       size_t offset = b.j["bufferViews"][view]["byteOffset"];
       b.bin[offset + 4] = 7;
       return b.write(d, "j");
     }},
    // Found by the glTF fuzzer: a float accessor's 1e24 as an index was cast to an integer.
    {"float_index_past_every_integer", "index 1 = 1.20892582e+24 names no vertex of 4",
     [](const std::string &d) {
       auto b = quad();
       int idx = b.j["meshes"][0]["primitives"][0]["indices"];
       b.j["accessors"][size_t(idx)]["componentType"] = 5126;
       b.j["accessors"][size_t(idx)]["count"] = 3;
       poke(b, idx, 0, 0.0f);
       poke(b, idx, 1, std::ldexp(1.0f, 80)); // exact in a float
       poke(b, idx, 2, 2.0f);
       return b.write(d, "fi");
     }},
    {"fractional_joint", "uses joint 0.5 but the skin has 2",
     [](const std::string &d) {
       auto b = quad();
       int joints = b.floats({0, 1, 0, 0, 0.5f, 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, "VEC4");
       b.j["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"] = joints;
       return b.write(d, "fj");
     }},
    {"negative_weight", "negative weight",
     [](const std::string &d) {
       auto b = quad();
       poke(b, 2, 1, -0.5f);
       return b.write(d, "w");
     }},
    {"all_zero_weights", "no vertex has a joint weight (vertex 0 has all-zero weights)",
     [](const std::string &d) {
       auto b = quad();
       for (int k : {0, 4, 8, 9, 12, 13}) // every vertex's (one weighted vertex repairs the rest)
         poke(b, 2, k, 0.0f);
       return b.write(d, "z");
     }},
    {"skin_without_joints", "skin 0 has no joints",
     [](const std::string &d) {
       auto b = quad();
       b.j["skins"][0]["joints"] = nlohmann::json::array();
       b.j["skins"][0].erase("inverseBindMatrices");
       return b.write(d, "s");
     }},
    {"cyclic_nodes", "cycle",
     [](const std::string &d) {
       auto b = quad();
       b.j["nodes"][1]["children"] = {0};
       return b.write(d, "c");
     }},
    {"lines_primitive", "mesh has no triangles: its primitives draw points or lines",
     [](const std::string &d) {
       auto b = quad();
       b.j["meshes"][0]["primitives"][0]["mode"] = 1;
       return b.write(d, "l");
     }},
    {"undefined_primitive_mode", "mode 9 is not a glTF primitive mode",
     [](const std::string &d) {
       auto b = quad();
       b.j["meshes"][0]["primitives"][0]["mode"] = 9;
       return b.write(d, "m");
     }},
    {"empty_mesh", "mesh has no triangles",
     [](const std::string &d) {
       auto b = quad();
       int empty = b.accessor(std::vector<uint16_t>{0, 0}, 5123, "SCALAR");
       b.j["accessors"][size_t(empty)]["count"] = 0;
       b.j["meshes"][0]["primitives"][0]["indices"] = empty;
       return b.write(d, "e");
     }},
    {"unsupported_required_extension", "unsupported required extension KHR_draco_mesh_compression",
     [](const std::string &d) {
       auto b = quad();
       b.j["extensionsUsed"] = {"KHR_draco_mesh_compression"};
       b.j["extensionsRequired"] = {"KHR_draco_mesh_compression"};
       return b.write(d, "x");
     }},
    {"meshopt_view_outside_its_buffer",
     "bufferViews[0] EXT_meshopt_compression: bytes [1048576, +16) lie outside its buffer",
     [](const std::string &d) {
       auto b = quad();
       b.j["extensionsUsed"] = {"EXT_meshopt_compression"};
       b.j["extensionsRequired"] = {"EXT_meshopt_compression"};
       // gltfpack -c's placeholder: a buffer with no data; the view's compressed bytes lie past
       // the end of the buffer it names.
       b.j["buffers"].push_back({{"byteLength", 1 << 20}});
       b.j["bufferViews"][0]["buffer"] = 1;
       b.j["bufferViews"][0]["extensions"]["EXT_meshopt_compression"] = {
           {"buffer", 0}, {"byteOffset", 1 << 20}, {"byteLength", 16}, {"byteStride", 4},
           {"count", 4},  {"mode", "ATTRIBUTES"}};
       return b.write(d, "mo", true);
     }},
    {"ktx2_textures",
     "unsupported required extension KHR_texture_basisu (textures crowdbake does not decode: "
     "export PNG, JPEG or WebP textures, e.g. gltfpack without -tc)",
     [](const std::string &d) {
       auto b = quad();
       b.j["extensionsUsed"] = {"KHR_texture_basisu"};
       b.j["extensionsRequired"] = {"KHR_texture_basisu"};
       return b.write(d, "ktx");
     }},
    {"uv_transform_overflow", "UV past the range of a number",
     [](const std::string &d) {
       auto b = quad();
       auto &prim = b.j["meshes"][0]["primitives"][0];
       prim["attributes"]["TEXCOORD_0"] = b.floats({0, 0, 2, 0, 0, 2, 2, 2}, "VEC2");
       prim["material"] = 0;
       const nlohmann::json huge = {{"scale", {1e308, 1e308}}};
       b.j["materials"] = {
           {{"pbrMetallicRoughness",
             {{"baseColorTexture",
               {{"index", 0}, {"extensions", {{"KHR_texture_transform", huge}}}}}}}}};
       b.j["textures"] = {{{"source", 0}}};
       const int bytes = b.accessor(std::vector<uint8_t>{1, 2, 3, 4}, 5121, "SCALAR");
       b.j["images"] = {{{"bufferView", b.j["accessors"][size_t(bytes)]["bufferView"]},
                         {"mimeType", "image/png"}}};
       return b.write(d, "uvt");
     }},
    {"absurd_count", "over the limit of",
     [](const std::string &d) {
       auto b = quad();
       b.j["accessors"][3]["count"] = 1099511627776LL;
       return b.write(d, "big");
     }},
    {"buffer_view_outside_buffer", "lies outside buffer",
     [](const std::string &d) {
       auto b = quad();
       b.j["bufferViews"][0]["byteOffset"] = 100000;
       return b.write(d, "bv");
     }},
    {"not_json", "not a readable glTF",
     [](const std::string &d) {
       std::ofstream(d + "/bad.gltf") << "{ this is not json";
       return d + "/bad.gltf";
     }},
    {"missing_file", "cannot open file", [](const std::string &d) { return d + "/nothing.glb"; }},
    {"joint_node_missing", "/skins/0/joints/1: index 42 names nothing",
     [](const std::string &d) {
       auto b = quad();
       b.j["skins"][0]["joints"][1] = 42;
       return b.write(d, "jn");
     }},
    {"key_times_decreasing", "key times decrease",
     [](const std::string &d) {
       auto b = quad();
       b.animation("back", 1, "translation", {1, 0}, {0, 0, 0, 0, 1, 0});
       return b.write(d, "kt");
     }},
};

void PrintTo(const Case &c, std::ostream *os) { *os << c.name; }

class Malformed : public ::testing::TestWithParam<Case> {};

TEST_P(Malformed, ExitsOneWithOneLineError) {
  const Case &c = GetParam();
  std::string dir = crowd::test::tempDir(std::string("robust_") + c.name);
  std::string input = c.make(dir);
  expectOneLineError(crowdbake("anim " + input + " -o " + dir + "/out.crowdpack --quiet"),
                     c.expected);
  EXPECT_FALSE(fs::exists(dir + "/out.crowdpack")) << "a failed bake must leave no pack";
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Inputs, Malformed, ::testing::ValuesIn(kCases),
                         [](const auto &info) { return std::string(info.param.name); });

TEST(Malformed, TheValidQuadBakes) {
  std::string dir = crowd::test::tempDir("robust_valid");
  std::string input = quad().write(dir, "ok");
  CliRun r = crowdbake("anim " + input + " -o " + dir + "/out.crowdpack --quiet");
  EXPECT_EQ(r.code, 0) << r.err;
  fs::remove_all(dir);
}

TEST(Usage, BadUsageExitsTwo) {
  EXPECT_EQ(crowdbake("").code, 2);
  EXPECT_EQ(crowdbake("frobnicate").code, 2);
  EXPECT_EQ(crowdbake("anim a.glb").code, 2);
  EXPECT_EQ(crowdbake("anim a.glb -o x --fps banana").code, 2);
  EXPECT_EQ(crowdbake("anim a.glb -o x --precision triple").code, 2);
  EXPECT_EQ(crowdbake("anim --help").code, 0);
  EXPECT_EQ(crowdbake("impostor a.glb -o x --views 32").code, 2);
  EXPECT_EQ(crowdbake("impostor a.glb -o x --texels 2").code, 2);
  EXPECT_EQ(crowdbake("impostor a.glb -o x --texels 12x").code, 2);
  EXPECT_EQ(crowdbake("impostor a.glb -o x --texels -4294967200").code, 2); // no wrap to 96
  EXPECT_EQ(crowdbake("impostor a.glb -o x --texels auto").code, 2);        // no --switch-distance
  EXPECT_EQ(crowdbake("impostor a.glb -o x --switch-distance 5").code, 2);  // without auto
  EXPECT_EQ(crowdbake("impostor --help").code, 0);
  EXPECT_EQ(crowdbake("lod a.glb").code, 2);
  EXPECT_EQ(crowdbake("lod a.glb -o x --floor 2").code, 2);
  EXPECT_EQ(crowdbake("lod --help").code, 0);
}

// The resource guard: past --max-memory or --max-seconds a bake stops with one error line naming
// the limit and leaves nothing behind (no pack, no report, no temporary file). The impostor bake
// below rasterises 256 views x 64 frames at 256^2 texels, seconds of work, so either limit is
// crossed at the guard's first sample, whatever the machine's speed.
TEST(ResourceGuard, StopsPastEitherLimitAndWritesNothing) {
  std::string dir = crowd::test::tempDir("robust_guard");
  std::string input = quad().write(dir, "q");
  const std::string bake = "impostor " + input + " -o " + dir + "/out.crowdpack --report " + dir +
                           "/out.report.json --frames 64 --texels 256 --quiet ";
  expectOneLineError(crowdbake(bake + "--max-memory 1"), "over --max-memory 1 MiB");
  expectOneLineError(crowdbake(bake + "--max-seconds 0.001"), "over --max-seconds 0.001 s");
  for (const auto &e : fs::directory_iterator(dir))
    EXPECT_TRUE(e.path().filename().string().rfind("q.", 0) == 0) << "left behind: " << e.path();
  fs::remove_all(dir);
}

// A cloth cache that is not there, or is a folder, is named as such before anything is baked.
TEST(ClothCache, AMissingOrFolderCacheIsNamed) {
  std::string dir = crowd::test::tempDir("robust_cache");
  std::string input = quad().write(dir, "q");
  const std::string rest = " --body " + input + " --outfit q=" + input +
                           " --garment skin --clip wave --fps 8 -o " + dir +
                           "/out.crowdpack --quiet";
  expectOneLineError(crowdbake("cloth " + dir + "/missing.pc2" + rest),
                     "missing.pc2: no such file");
  fs::create_directory(dir + "/folder.pc2");
  expectOneLineError(crowdbake("cloth " + dir + "/folder.pc2" + rest),
                     "folder.pc2: not a regular file");
  EXPECT_FALSE(fs::exists(dir + "/out.crowdpack"));
  fs::remove_all(dir);
}

// A damaged pack fails verify with a message naming what is wrong.
TEST(DamagedPack, TruncatedAndBitFlippedPacksFailVerify) {
  std::string dir = crowd::test::tempDir("robust_pack");
  std::string input = quad().write(dir, "q");
  ASSERT_EQ(crowdbake("anim " + input + " -o " + dir + "/p.crowdpack --quiet").code, 0);
  std::ifstream f(dir + "/p.crowdpack", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_EQ(crowdbake("verify " + dir + "/p.crowdpack").code, 0);

  std::ofstream(dir + "/t.crowdpack", std::ios::binary) << bytes.substr(0, bytes.size() - 100);
  expectOneLineError(crowdbake("verify " + dir + "/t.crowdpack"), "truncated");

  std::string flipped = bytes; // a byte of the mesh's payload (not padding between chunks)
  const crowd::pack::Reader reader(std::vector<uint8_t>(bytes.begin(), bytes.end()), "p");
  const auto *mesh = reader.find(crowd::pack::kMesh);
  ASSERT_NE(mesh, nullptr);
  flipped[mesh->offset + mesh->size / 2] ^= 0x10;
  std::ofstream(dir + "/f.crowdpack", std::ios::binary) << flipped;
  expectOneLineError(crowdbake("verify " + dir + "/f.crowdpack"), "checksum mismatch");

  std::string magic = bytes;
  magic[0] = 'X';
  std::ofstream(dir + "/m.crowdpack", std::ios::binary) << magic;
  expectOneLineError(crowdbake("verify " + dir + "/m.crowdpack"), "bad magic");
  fs::remove_all(dir);
}

// A pack whose clip table was emptied, its checksums recomputed (what a bad tool or a
// hand edit writes), crashed export (it previews the first clip). The loader every consumer uses
// now rejects a texture whose frames belong to no clip: one line each, naming the chunk.
TEST(DamagedPack, FramesThatNoClipOwnsAreRejectedByEveryConsumer) {
  std::string dir = crowd::test::tempDir("robust_clips");
  crowd::test::GltfBuilder waving; // the quad with clip "wave" (2 s)
  waving.morphedQuad(2);
  std::string input = waving.write(dir, "q");
  ASSERT_EQ(crowdbake("anim " + input + " -o " + dir + "/p.crowdpack --store texture --quiet").code,
            0);
  crowd::pack::AnimationPack p =
      crowd::pack::loadAnimationPack(crowd::pack::Reader::open(dir + "/p.crowdpack"));
  ASSERT_EQ(p.clips.size(), 1u);
  ASSERT_GT(p.animation.frameCount, 2u);
  const std::string noClips = dir + "/no_clips.crowdpack", short_ = dir + "/short.crowdpack";
  auto emptied = p;
  emptied.clips.clear();
  crowd::pack::writePack(emptied, noClips);
  auto shortened = p; // the first clip one frame short: the texture's last frame is no clip's
  shortened.clips.resize(1);
  shortened.clips[0].frameCount = p.animation.frameCount - 1;
  crowd::pack::writePack(shortened, short_);
  const std::string none = "chunk CLIP, field 'clip count': no clips, and frame 0 of the",
                    last = "frame " + std::to_string(p.animation.frameCount - 1) + " of the";
  expectOneLineError(crowdbake("verify " + noClips), none);
  expectOneLineError(crowdbake("export " + noClips + " --images " + dir + "/images"), none);
  expectOneLineError(crowdbake("pose " + noClips + " -o " + dir + "/pose.ply"), none);
  expectOneLineError(crowdbake("verify " + short_), last);
  fs::remove_all(dir);
}

} // namespace
