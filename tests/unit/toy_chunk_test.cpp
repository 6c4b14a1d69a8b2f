// One room per chunk type: a toy chunk ("TOYS", a counter and a 2x2 image) defined here alone,
// registered with the chunk registry, then carried through what inspect, verify, export's images
// and diff do with a pack, with no other file knowing it.
#include <gtest/gtest.h>

#include "crowd/bake/pack_diff.h"
#include "crowd/bake/pack_images.h"
#include "crowd/formats/bytes.h"
#include "crowd/formats/chunks.h"
#include "crowd/formats/registry.h"
#include "sample_character.h"

using namespace crowd;

namespace {

constexpr uint32_t kToys = pack::fourcc("TOYS");

uint32_t decodeCount(std::span<const uint8_t> bytes, const std::string &context) {
  pack::ByteReader r(bytes, context);
  const uint32_t count = r.get<uint32_t>("count");
  r.expectEnd();
  return count;
}

pack::Description describeToys(std::span<const uint8_t> bytes, uint32_t, const std::string &ctx) {
  pack::Description d;
  d.add("count", pack::number(decodeCount(bytes, ctx)));
  return d;
}

std::vector<pack::Image> toyImages(std::span<const uint8_t> bytes, uint32_t,
                                   const std::string &ctx) {
  const uint8_t v = uint8_t(decodeCount(bytes, ctx));
  return {{"toys", 2, 2, 1, pack::Image::Pixel::U8, {v, v, v, v}}};
}

std::vector<uint8_t> packWithToys(uint32_t count) {
  pack::ByteWriter toys;
  toys.put<uint32_t>(count);
  std::vector<uint8_t> bytes = pack::packBytes(test::sampleHumanoidLodPack());
  const pack::Reader plain(bytes, "plain");
  pack::Writer w;
  for (const auto &c : plain.chunks()) {
    const auto payload = plain.payload(c);
    w.add(c.type, c.version, {payload.begin(), payload.end()});
  }
  w.add(kToys, 1, toys.take());
  return w.bytes();
}

TEST(ToyChunk, ARegisteredTypeGoesThroughInspectVerifyExportAndDiff) {
  if (!pack::findCodec(kToys))
    pack::registerChunkCodec({kToys, "toy counter", 1, 1, describeToys, toyImages});
  EXPECT_THROW(pack::registerChunkCodec({kToys, "again", 1, 1, describeToys}), Error);

  const auto three = packWithToys(3), four = packWithToys(4);
  const pack::Reader a(three, "three"), b(four, "four");
  const pack::ChunkEntry &toys = *a.find(kToys);
  // inspect: the chunk described by its codec.
  const pack::Description d = pack::codecOf(toys, "toys").describe(a.payload(toys), 1, "toys");
  ASSERT_EQ(d.fields.size(), 1u);
  EXPECT_EQ(d.fields[0].value.text, "3");
  // verify: a known type and version; the character's own chunks still cross-checked.
  EXPECT_NE(pack::verifyPack(a).find("22 joints"), std::string::npos);
  // export: its image beside the pack's others.
  bool exported = false;
  for (const pack::Image &image : packImages(a))
    exported |= image.name == "toys" && image.bytes == std::vector<uint8_t>(4, 3);
  EXPECT_TRUE(exported);
  // diff: the same chunk passes; another count fails, naming the field.
  EXPECT_EQ(diffPacks(a, pack::Reader(three, "again"), {}).verdict, DiffVerdict::Pass);
  const PackDiff changed = diffPacks(a, b, {});
  EXPECT_EQ(changed.verdict, DiffVerdict::Fail);
  bool named = false;
  for (const DiffItem &i : changed.items)
    named |= i.chunk == "TOYS" && i.worst.find("field 'count': 3 -> 4") != std::string::npos;
  EXPECT_TRUE(named);
  // Version bounds stay the registry's: a TOYS chunk of version 2 is refused, named.
  pack::Writer w2;
  w2.add(kToys, 2, {0, 0, 0, 0});
  const auto v2 = w2.bytes();
  try {
    pack::codecOf(pack::Reader(v2, "v2").chunks()[0], "v2, chunk TOYS");
    ADD_FAILURE() << "version 2 was read";
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("chunk version 2 is not supported"), std::string::npos);
  }
}

} // namespace
