// The PNG check before the decoder (support/src/images/png_check.h): whole PNGs pass and decode,
// every cut and every flipped byte is turned away with a reason, as are lying headers and rows
// that do not add up (an interlaced image's seven passes counted by hand here).
#include <gtest/gtest.h>
#include <zlib.h>

#include "../../support/src/images/png_check.h"
#include "crowd/support/images.h"

namespace crowd::images {
namespace {

void put32(std::vector<uint8_t> &out, uint32_t v) {
  for (int s = 24; s >= 0; s -= 8)
    out.push_back(uint8_t(v >> s));
}

void chunk(std::vector<uint8_t> &out, const char *type, const std::vector<uint8_t> &data) {
  put32(out, uint32_t(data.size()));
  const size_t at = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data.begin(), data.end());
  put32(out, uint32_t(crc32(0, &out[at], uInt(4 + data.size()))));
}

// An RGBA8 PNG whose IDAT inflates to `rawBytes` zero bytes.
std::vector<uint8_t> png(uint32_t width, uint32_t height, bool interlaced, size_t rawBytes) {
  std::vector<uint8_t> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'}, header;
  put32(header, width);
  put32(header, height);
  header.insert(header.end(), {8, 6, 0, 0, uint8_t(interlaced)});
  chunk(out, "IHDR", header);
  std::vector<uint8_t> raw(rawBytes, 0), packed(compressBound(uLong(rawBytes)));
  uLongf size = packed.size();
  EXPECT_EQ(compress(packed.data(), &size, raw.data(), uLong(raw.size())), Z_OK);
  packed.resize(size);
  chunk(out, "IDAT", packed);
  chunk(out, "IEND", {});
  return out;
}

TEST(PngCheck, AWholePngPassesAndDecodes) {
  pack::Image image{"a", 4, 3, 4, pack::Image::Pixel::U8, std::vector<uint8_t>(48, 200)};
  const auto bytes = encodePng(image);
  std::string why;
  EXPECT_TRUE(pngIsWhole(bytes, 8192, why)) << why;
  pack::Image back;
  EXPECT_TRUE(decode(bytes, "image.png", 8192, back, why)) << why;
  EXPECT_EQ(back.bytes, image.bytes);
}

TEST(PngCheck, EveryCutAndEveryFlippedByteIsTurnedAway) {
  const auto whole =
      encodePng(pack::Image{"b", 5, 2, 3, pack::Image::Pixel::U8, std::vector<uint8_t>(30, 7)});
  std::string why;
  for (size_t cut = 0; cut < whole.size(); ++cut) {
    why.clear();
    EXPECT_FALSE(pngIsWhole({whole.begin(), whole.begin() + long(cut)}, 8192, why)) << cut;
    EXPECT_FALSE(why.empty()) << cut;
  }
  for (size_t at = 0; at < whole.size(); ++at) {
    auto flipped = whole;
    flipped[at] ^= 0xff;
    EXPECT_FALSE(pngIsWhole(flipped, 8192, why)) << "byte " << at;
  }
}

TEST(PngCheck, SidesPastTheLimitAreRefusedBeforeAnyDecoding) {
  std::string why;
  EXPECT_FALSE(pngIsWhole(png(60000, 60000, false, 16), 8192, why));
  EXPECT_EQ(why, "PNG 60000x60000 is outside 1..8192");
  EXPECT_FALSE(pngIsWhole(png(0, 4, false, 16), 8192, why));
  EXPECT_EQ(why, "PNG 0x4 is outside 1..8192");
}

TEST(PngCheck, RowsMustAddUpToTheHeader) {
  // 5x3 RGBA, filter byte + 4 bytes a pixel. Plain: 3 rows of 1 + 20. Adam7's passes (pass:
  // width x height): 1: 1x1, 2: 1x1, 3: 2x0, 4: 1x1, 5: 3x1, 6: 2x2, 7: 5x1, so
  // 5 + 5 + 0 + 5 + 13 + 2 * 9 + 21 = 67 bytes.
  std::string why;
  EXPECT_TRUE(pngIsWhole(png(5, 3, false, 63), 8192, why)) << why;
  EXPECT_TRUE(pngIsWhole(png(5, 3, true, 67), 8192, why)) << why;
  pack::Image decoded;
  EXPECT_TRUE(decode(png(5, 3, true, 67), "image.png", 8192, decoded, why)) << why;
  for (size_t wrong : {66u, 68u}) {
    EXPECT_FALSE(pngIsWhole(png(5, 3, true, wrong), 8192, why)) << wrong;
    EXPECT_NE(why.find("bytes of rows"), std::string::npos) << why;
  }
}

} // namespace
} // namespace crowd::images
