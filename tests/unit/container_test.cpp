#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>

#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "crowd/formats/chunks.h"
#include "crowd/formats/error.h"
#include "crowd/formats/registry.h"

using namespace crowd::pack;

namespace {

AnimationPack tinyPack() {
  AnimationPack p;
  p.provenance = {"test", {{"fps", "30"}}, {{"in.glb", 10, "farmhash64:0"}}};
  p.skeleton.names = {"root", "child"};
  p.skeleton.parents = {-1, 0};
  p.skeleton.inverseBind.assign(32, 0.0f);
  for (int k = 0; k < 4; ++k)
    p.skeleton.inverseBind[size_t(k * 5)] = p.skeleton.inverseBind[size_t(16 + k * 5)] = 1;
  p.clips = {{"walk", 30, 0, 0, 2, false}};
  p.animation.width = 6;
  p.animation.height = 2;
  p.animation.jointCount = 2;
  p.animation.framesPerRow = 1;
  p.animation.frameCount = 2;
  p.animation.texels.assign(6 * 2 * 16, 0);
  p.skin.width = 6;
  p.skin.height = 1;
  p.skin.vertexCount = 3;
  p.skin.texels.assign(24, 0.0f);
  for (int v = 0; v < 3; ++v)
    p.skin.texels[size_t(v * 8 + 4)] = 1;
  p.mesh.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  p.mesh.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1};
  p.mesh.indices = {0, 1, 2};
  p.mesh.subMeshes = {{"body", 0, 3}};
  p.mesh.boundingSphere = {0.5f, 0.5f, 0, 1};
  p.sources = SourceMap::of({{0, 1, 0, 0, 2}, {0, 1, 0, 0, 0}, {}}); // the last: made by a bake
  return p;
}

TEST(Container, RoundTripsEveryChunk) {
  auto bytes = packBytes(tinyPack());
  EXPECT_EQ(bytes.size() % kAlignment, 0u);
  Reader r(bytes, "mem");
  for (const auto &c : r.chunks())
    EXPECT_EQ(c.offset % kAlignment, 0u) << fourccName(c.type);
  AnimationPack back = loadAnimationPack(r);
  EXPECT_EQ(back.skeleton.names, tinyPack().skeleton.names);
  EXPECT_EQ(back.clips[0].name, "walk");
  EXPECT_EQ(back.mesh.indices, tinyPack().mesh.indices);
  EXPECT_EQ(back.provenance.settings, tinyPack().provenance.settings);
  ASSERT_TRUE(back.sources.has_value());
  EXPECT_EQ(back.sources->expand(), tinyPack().sources->expand());
  EXPECT_EQ(packBytes(back), bytes) << "decode then encode must give the same bytes";
}

TEST(Container, EveryTruncationIsAnError) {
  auto bytes = packBytes(tinyPack());
  for (size_t n = 0; n < bytes.size(); ++n) {
    std::vector<uint8_t> cut(bytes.begin(), bytes.begin() + long(n));
    EXPECT_THROW(loadAnimationPack(Reader(cut, "cut")), crowd::Error) << "length " << n;
  }
}

TEST(Container, EveryBitFlipIsCaught) {
  auto bytes = packBytes(tinyPack());
  size_t caught = 0, flips = 0;
  for (size_t i = 0; i < bytes.size(); ++i) {
    std::vector<uint8_t> bad = bytes;
    bad[i] ^= 0x04;
    ++flips;
    try {
      loadAnimationPack(Reader(bad, "flip"));
    } catch (const crowd::Error &) {
      ++caught;
      continue;
    }
    // Only padding and reserved bytes may change without notice.
    Reader r(bytes, "ok");
    bool inPayload = false;
    for (const auto &c : r.chunks())
      inPayload |= i >= c.offset && i < c.offset + c.size;
    EXPECT_FALSE(inPayload || i < kHeaderSize - 4) << "undetected flip at byte " << i;
  }
  EXPECT_GT(caught, flips / 2);
}

// A chunk table entry (its checksums made good) whose offset points past the end of the file, at
// any size: named as outside the file, never read (an unsigned `size - offset` would wrap there).
TEST(Container, AChunkPastTheEndOfTheFileIsNamed) {
  const auto bytes = packBytes(tinyPack());
  for (uint64_t past : {uint64_t(kAlignment), uint64_t(4096), uint64_t(1) << 40}) {
    for (uint64_t size : {uint64_t(0), uint64_t(16)}) {
      std::vector<uint8_t> bad = bytes;
      const uint64_t offset = bytes.size() + past;
      std::memcpy(&bad[kHeaderSize + 8], &offset, 8); // the first entry: type, version, offset
      std::memcpy(&bad[kHeaderSize + 16], &size, 8);
      const uint32_t empty = crc32({});
      std::memcpy(&bad[kHeaderSize + 24], &empty, 4);
      Reader good(bytes, "ok");
      const uint32_t table = crc32(std::span<const uint8_t>(bad).subspan(
          kHeaderSize, good.chunks().size() * kTableEntrySize));
      std::memcpy(&bad[24], &table, 4); // the header's table checksum
      try {
        Reader r(bad, "past");
        FAIL() << "offset " << offset << " size " << size << " was read";
      } catch (const crowd::Error &e) {
        EXPECT_NE(std::string(e.what()).find("lies outside the file"), std::string::npos)
            << e.what();
      }
    }
  }
}

TEST(Container, CrossChunkChecksNameTheField) {
  auto p = tinyPack();
  p.skin.texels[0] = 5; // joint 5 of 2
  try {
    loadAnimationPack(Reader(packBytes(p), "x.crowdpack"));
    FAIL();
  } catch (const crowd::Error &e) {
    EXPECT_NE(std::string(e.what()).find("chunk SKIN, field 'texels': vertex 0 uses joint 5"),
              std::string::npos)
        << e.what();
  }
  // A joint id no int holds (pack_consumer_fuzz: UB where the message cast it to int), and
  // negative, NaN or between two joints (the chunk's own checks): each named, never followed.
  for (float id : {5.76461e17f, -1.0f, NAN, 0.5f}) {
    p = tinyPack();
    p.skin.texels[0] = id;
    try {
      loadAnimationPack(Reader(packBytes(p), "x.crowdpack"));
      ADD_FAILURE() << "no error for joint id " << id;
    } catch (const crowd::Error &e) {
      EXPECT_NE(std::string(e.what()).find("chunk SKIN, field 'texels': "), std::string::npos)
          << e.what();
    }
  }
  p = tinyPack();
  p.mesh.indices[1] = 9;
  EXPECT_THROW(loadAnimationPack(Reader(packBytes(p), "x")), crowd::Error);
  p = tinyPack();
  p.skeleton.parents[0] = 1; // parent after child
  EXPECT_THROW(loadAnimationPack(Reader(packBytes(p), "x")), crowd::Error);
  p = tinyPack();
  p.clips[0].frameCount = 3; // past the texture
  EXPECT_THROW(loadAnimationPack(Reader(packBytes(p), "x")), crowd::Error);
  p = tinyPack();
  p.clips.push_back({"empty", 30, 0, 2, 0, false}); // no frames: nothing to play
  try {
    loadAnimationPack(Reader(packBytes(p), "x"));
    ADD_FAILURE() << "a clip without frames was read";
  } catch (const crowd::Error &e) {
    EXPECT_NE(std::string(e.what()).find("clip 'empty' has no frames"), std::string::npos)
        << e.what();
  }
}

TEST(Container, SourceMapsStayCompactAndFitTheMesh) {
  // Import order: two runs say it all, with no per-vertex ordinal.
  std::vector<VertexSource> inOrder;
  for (int32_t prim = 0; prim < 2; ++prim)
    for (int32_t v = 0; v < 100; ++v)
      inOrder.push_back({0, 3, 1, prim, v});
  const SourceMap compact = SourceMap::of(inOrder);
  EXPECT_EQ(compact.runs.size(), 2u);
  EXPECT_TRUE(compact.ordinals.empty());
  EXPECT_EQ(compact.expand(), inOrder);
  // Reordered (as LOD does) with a made vertex: one ordinal per vertex, same sources back.
  std::vector<VertexSource> shuffled(inOrder.rbegin(), inOrder.rend());
  shuffled.insert(shuffled.begin() + 7, VertexSource{});
  const SourceMap reordered = SourceMap::of(shuffled);
  EXPECT_EQ(reordered.ordinals.size(), shuffled.size());
  EXPECT_EQ(reordered.ordinals[7], SourceMap::kMade);
  EXPECT_EQ(reordered.expand(), shuffled);
  const auto bytes = encode(reordered);
  EXPECT_EQ(decodeSourceMap(bytes, "t").expand(), shuffled);
  // A map of another mesh's size is refused, naming the chunk.
  auto p = tinyPack();
  p.sources = compact;
  try {
    loadAnimationPack(Reader(packBytes(p), "x.crowdpack"));
    FAIL();
  } catch (const crowd::Error &e) {
    EXPECT_NE(std::string(e.what()).find("chunk SRCV: sized for another mesh (200 vertices"),
              std::string::npos)
        << e.what();
  }
  // Negative indices and ordinals past the runs are refused.
  SourceMap bad = compact;
  bad.runs[0].first.vertex = -3;
  EXPECT_THROW(decodeSourceMap(encode(bad), "t"), crowd::Error);
  bad = reordered;
  bad.ordinals[0] = 5000;
  EXPECT_THROW(decodeSourceMap(encode(bad), "t"), crowd::Error);
}

TEST(Container, OptionalDiffuseTextureRoundTripsAndNeedsUvs) {
  auto p = tinyPack();
  p.mesh.uvs = {0, 0, 1, 0, 0, 1};
  p.diffuse = Texture{2, 1, {255, 0, 0, 255, 0, 255, 0, 255}};
  auto back = loadAnimationPack(Reader(packBytes(p), "t"));
  ASSERT_TRUE(back.diffuse.has_value());
  EXPECT_EQ(back.diffuse->rgba, p.diffuse->rgba);
  EXPECT_FALSE(loadAnimationPack(Reader(packBytes(tinyPack()), "t")).diffuse.has_value());
  p.mesh.uvs.clear();
  EXPECT_THROW(loadAnimationPack(Reader(packBytes(p), "t")), crowd::Error);
  p = tinyPack();
  p.mesh.uvs = {0, 0, 1, 0, 0, 1};
  p.diffuse = Texture{3, 1, {1, 2, 3}}; // too few texels
  EXPECT_THROW(loadAnimationPack(Reader(packBytes(p), "t")), crowd::Error);
}

// Opening refuses what is not a regular file before reading a byte: a FIFO with no writer, or
// /dev/zero, read whole before, blocked or grew until memory ran out.
TEST(Container, OpenRefusesWhatIsNotARegularFile) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("crowd_open_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  ASSERT_EQ(::mkfifo((dir / "fifo.crowdpack").c_str(), 0600), 0);
  const std::pair<std::string, std::string> cases[] = {
      {(dir / "fifo.crowdpack").string(), "not a regular file (a FIFO): nothing read"},
      {"/dev/zero", "not a regular file (a device): nothing read"},
      {dir.string(), "not a regular file (a folder): nothing read"},
      {(dir / "missing.crowdpack").string(), "cannot open file (No such file or directory)"}};
  for (const auto &[path, why] : cases) {
    try {
      Reader::open(path);
      ADD_FAILURE() << path << " opened";
    } catch (const crowd::Error &e) {
      EXPECT_EQ(std::string(e.what()), "pack '" + path + "': " + why);
    }
  }
  std::filesystem::remove_all(dir);
}

TEST(Half, RoundTripsEveryHalfAndRoundsToNearestEven) {
  for (uint32_t h = 0; h < 65536; ++h) {
    float f = halfToFloat(uint16_t(h));
    if (std::isnan(f))
      continue;
    ASSERT_EQ(floatToHalf(f), h) << std::hex << h;
  }
  EXPECT_EQ(halfToFloat(floatToHalf(1.0f + 1.0f / 4096)), 1.0f); // tie goes to even
  EXPECT_EQ(floatToHalf(1e-10f), 0u);                            // far below subnormals
  EXPECT_EQ(floatToHalf(-2e-10f), 0x8000u);
  EXPECT_EQ(floatToHalf(1e6f), 0x7c00u);                         // overflow to infinity
  EXPECT_NEAR(halfToFloat(floatToHalf(6e-8f)), 5.96e-8f, 1e-9f); // smallest subnormal
}

// The registry (inspect, verify, export): every chunk a pack writes has a codec that describes
// it; an unknown type or version and a cross-chunk disagreement each fail verify, naming it.
TEST(Registry, DescribesEveryChunkAndVerifyNamesWhatIsWrong) {
  Reader r(packBytes(tinyPack()), "mem");
  for (size_t i = 0; i < r.chunks().size(); ++i) {
    const auto &c = r.chunks()[i];
    const ChunkCodec &codec = codecOf(c, chunkContext(r, i));
    EXPECT_EQ(codec.version, c.version) << "the version written is the codec's";
    Description d = codec.describe(r.payload(c), c.version, chunkContext(r, i));
    EXPECT_FALSE(d.fields.empty() && d.tables.empty()) << fourccName(c.type);
  }
  const ChunkCodec *skeleton = findCodec(kSkeleton);
  ASSERT_NE(skeleton, nullptr);
  Description d = skeleton->describe(r.payload(r.require(kSkeleton)), 1, "s");
  ASSERT_EQ(d.tables.size(), 1u);
  EXPECT_EQ(d.tables[0].rows.size(), 2u);
  EXPECT_EQ(d.tables[0].rows[1][1].text, "child");
  EXPECT_EQ(verifyPack(r), std::to_string(r.chunks().size()) + " chunks, " +
                               std::to_string(r.fileSize()) + " bytes, 2 joints, 1 clips");

  auto expectVerifyError = [](const Writer &w, const std::string &needle) {
    try {
      verifyPack(Reader(w.bytes(), "w"));
      ADD_FAILURE() << "verify accepted a pack that should fail with: " << needle;
    } catch (const crowd::Error &e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  auto copyOf = [&](uint32_t skip) {
    Writer w;
    for (const auto &c : r.chunks())
      if (c.type != skip)
        w.add(c.type, c.version, {r.payload(c).begin(), r.payload(c).end()});
    return w;
  };
  Writer unknown = copyOf(0);
  unknown.add(fourcc("ZZZZ"), 1, {1, 2, 3});
  expectVerifyError(unknown, "chunk ZZZZ: not a chunk type this build knows");
  Writer future = copyOf(kLod);
  future.add(kLod, kChunkVersion + 1, {});
  expectVerifyError(future, "chunk LODS: chunk version 2 is not supported (this build reads 1..1)");
  expectVerifyError(copyOf(kSkinTexture), "SKIN");
}

} // namespace

namespace {
// docs/pack_format.md describes each chunk under a heading "### `TYPE` title, version N" (or
// "versions A-B"): the registry's types and the versions each reads, exactly, no more, no less.
TEST(PackFormatDoc, DescribesEveryChunkTypeAndVersionTheRegistryKnows) {
  std::ifstream in(std::string(CROWD_SOURCE_DIR) + "/docs/pack_format.md");
  ASSERT_TRUE(in) << "docs/pack_format.md is missing";
  const std::regex heading(R"(^### `(\w{4})` .*, versions? (\d+)(?:-(\d+))?$)");
  std::map<std::string, std::pair<uint32_t, uint32_t>> described;
  for (std::string line; std::getline(in, line);)
    if (std::smatch m; std::regex_match(line, m, heading)) {
      const uint32_t from = uint32_t(std::stoul(m[2])),
                     to = m[3].matched ? uint32_t(std::stoul(m[3])) : from;
      EXPECT_TRUE(described.emplace(m[1], std::pair{from, to}).second) << m[1] << " twice";
    } else {
      EXPECT_FALSE(line.starts_with("### `")) << "a chunk heading out of the pattern: " << line;
    }
  for (const auto &codec : chunkCodecs()) {
    const std::string type = fourccName(codec.type);
    const auto it = described.find(type);
    if (it == described.end()) {
      ADD_FAILURE() << "chunk " << type << " (" << codec.title << ") is not described";
      continue;
    }
    EXPECT_EQ(it->second, std::pair(codec.oldestVersion, codec.version))
        << "chunk " << type << ": the document describes versions " << it->second.first << "-"
        << it->second.second << ", the registry reads " << codec.oldestVersion << "-"
        << codec.version;
    described.erase(it);
  }
  for (const auto &[type, versions] : described)
    ADD_FAILURE() << "the document describes " << type << ", which the registry does not know";
}
} // namespace
