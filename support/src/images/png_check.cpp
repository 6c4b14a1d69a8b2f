#include "png_check.h"

#include <array>
#include <zlib.h>

namespace crowd::images {
namespace {

constexpr std::array<uint8_t, 8> kSignature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

uint32_t bigEndian(const uint8_t *p) {
  return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | p[3];
}

// Bytes of the filtered image data a width x height image of `bitsPerPixel` holds: a filter
// byte and the packed pixels per row, over Adam7's seven passes where interlaced.
uint64_t rawBytes(uint64_t width, uint64_t height, uint64_t bitsPerPixel, bool interlaced) {
  auto rows = [&](uint64_t w, uint64_t h) {
    return w && h ? h * (1 + (w * bitsPerPixel + 7) / 8) : 0;
  };
  if (!interlaced)
    return rows(width, height);
  struct Pass {
    uint64_t x0, y0, dx, dy;
  };
  constexpr Pass kAdam7[] = {{0, 0, 8, 8}, {4, 0, 8, 8}, {0, 4, 4, 8}, {2, 0, 4, 4},
                             {0, 2, 2, 4}, {1, 0, 2, 2}, {0, 1, 1, 2}};
  uint64_t total = 0;
  for (const Pass &p : kAdam7)
    total += rows(width > p.x0 ? (width - p.x0 + p.dx - 1) / p.dx : 0,
                  height > p.y0 ? (height - p.y0 + p.dy - 1) / p.dy : 0);
  return total;
}

// Channels of a colour type where `depth` is allowed for it (PNG 1.2, 4.1.1), else 0.
int channelsOf(int colourType, int depth) {
  auto in = [depth](std::initializer_list<int> allowed) {
    for (int d : allowed)
      if (d == depth)
        return true;
    return false;
  };
  switch (colourType) {
  case 0:
    return in({1, 2, 4, 8, 16}) ? 1 : 0;
  case 2:
    return in({8, 16}) ? 3 : 0;
  case 3:
    return in({1, 2, 4, 8}) ? 1 : 0;
  case 4:
    return in({8, 16}) ? 2 : 0;
  case 6:
    return in({8, 16}) ? 4 : 0;
  default:
    return 0;
  }
}

} // namespace

bool isPng(const std::vector<uint8_t> &bytes) {
  return bytes.size() >= kSignature.size() &&
         std::equal(kSignature.begin(), kSignature.end(), bytes.begin());
}

bool pngIsWhole(const std::vector<uint8_t> &bytes, int maxSide, std::string &why) {
  auto fail = [&why](const std::string &reason) {
    why = "PNG " + reason;
    return false;
  };
  if (!isPng(bytes))
    return fail("signature missing");
  z_stream z{};
  if (inflateInit(&z) != Z_OK)
    return fail("check: cannot start zlib");
  struct End {
    z_stream &z;
    ~End() { inflateEnd(&z); }
  } end{z};
  std::array<uint8_t, 1 << 16> scratch; // the inflated bytes are counted, not kept
  uint64_t expected = 0, inflated = 0;
  bool header = false, palette = false, data = false, dataDone = false, streamEnd = false;
  int channels = 0, colourType = 0;
  for (size_t at = kSignature.size();;) {
    if (bytes.size() - at < 12)
      return fail(at == bytes.size() ? "cut before IEND" : "cut inside a chunk header");
    const uint32_t length = bigEndian(&bytes[at]);
    const std::string type(reinterpret_cast<const char *>(&bytes[at + 4]), 4);
    if (length > 0x7fffffffu || bytes.size() - at - 12 < length)
      return fail("chunk " + type + ": cut (" + std::to_string(length) + " bytes promised)");
    const uint8_t *body = &bytes[at + 8];
    if (crc32(crc32(0, &bytes[at + 4], 4), body, length) != bigEndian(body + length))
      return fail("chunk " + type + ": CRC mismatch");
    at += 12 + size_t(length);
    if (!header) {
      if (type != "IHDR" || length != 13)
        return fail("does not start with an IHDR chunk");
      const uint32_t width = bigEndian(body), height = bigEndian(body + 4);
      const int depth = body[8];
      colourType = body[9];
      if (width < 1 || height < 1 || width > uint32_t(maxSide) || height > uint32_t(maxSide))
        return fail(std::to_string(width) + "x" + std::to_string(height) + " is outside 1.." +
                    std::to_string(maxSide));
      channels = channelsOf(colourType, depth);
      if (!channels || body[10] != 0 || body[11] != 0 || body[12] > 1)
        return fail("IHDR: colour type " + std::to_string(colourType) + ", depth " +
                    std::to_string(depth) + ", methods " + std::to_string(body[10]) + "/" +
                    std::to_string(body[11]) + "/" + std::to_string(body[12]) + " are not PNG's");
      expected = rawBytes(width, height, uint64_t(channels) * uint64_t(depth), body[12] == 1);
      header = true;
      continue;
    }
    if (type == "IEND")
      break;
    if (type == "PLTE")
      palette = true;
    if (type != "IDAT") {
      dataDone = data;
      continue;
    }
    if (dataDone)
      return fail("IDAT chunks are not consecutive");
    if (colourType == 3 && !palette)
      return fail("palette colour type without a PLTE before IDAT");
    data = true;
    z.next_in = const_cast<Bytef *>(body);
    z.avail_in = length;
    while (z.avail_in > 0 && !streamEnd) {
      z.next_out = scratch.data();
      z.avail_out = uInt(scratch.size());
      const int rc = inflate(&z, Z_NO_FLUSH);
      inflated += scratch.size() - z.avail_out;
      if (rc == Z_STREAM_END)
        streamEnd = true;
      else if (rc != Z_OK && rc != Z_BUF_ERROR)
        return fail(std::string("IDAT: corrupt data (zlib: ") + (z.msg ? z.msg : "error") + ")");
      if (inflated > expected)
        return fail("IDAT: more data than its " + std::to_string(expected) + " bytes of rows");
    }
  }
  if (!data)
    return fail("no IDAT chunk");
  if (!streamEnd || inflated != expected)
    return fail("IDAT: " + std::to_string(inflated) + " bytes of rows where its header needs " +
                std::to_string(expected));
  return true;
}

} // namespace crowd::images
