#include "crowd/formats/bc5.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace crowd::pack {
namespace {

// The eight values (0..255 scale) a BC4 channel block with endpoints e0, e1 decodes to.
void levels(int e0, int e1, float out[8]) {
  out[0] = float(e0), out[1] = float(e1);
  if (e0 > e1) {
    for (int i = 2; i < 8; ++i)
      out[i] = (float(8 - i) * float(e0) + float(i - 1) * float(e1)) / 7.0f;
  } else {
    for (int i = 2; i < 6; ++i)
      out[i] = (float(6 - i) * float(e0) + float(i - 1) * float(e1)) / 5.0f;
    out[6] = 0, out[7] = 255;
  }
}

// One channel of 16 texels (0..255 scale, used[k] says which count) into 8 bytes, eight levels
// (e0 > e1): endpoints first at the rounded extremes, then twice the least-squares endpoints for
// the chosen indices, then each endpoint nudged by one, each kept where it lowers the squared
// error.
void encodeChannel(const float v[16], const bool used[16], uint8_t out[8]) {
  float lo = 255, hi = 0;
  for (int k = 0; k < 16; ++k)
    if (used[k])
      lo = std::min(lo, v[k]), hi = std::max(hi, v[k]);
  auto fit = [&](int e0, int e1, uint64_t &bits) {
    float lv[8];
    levels(e0, e1, lv);
    float total = 0;
    bits = 0;
    for (int k = 0; k < 16; ++k) {
      if (!used[k])
        continue;
      int best = 0;
      float bestD = std::abs(v[k] - lv[0]);
      for (int i = 1; i < 8; ++i)
        if (float d = std::abs(v[k] - lv[i]); d < bestD)
          bestD = d, best = i;
      total += bestD * bestD;
      bits |= uint64_t(best) << (3 * k);
    }
    return total;
  };
  int e0 = std::clamp(int(std::lround(hi)), 0, 255), e1 = std::clamp(int(std::lround(lo)), 0, 255);
  if (e0 == e1) // flat: one level, every index on it
    e0 == 0 ? ++e0 : --e1;
  uint64_t bits = 0;
  float best = fit(e0, e1, bits);
  auto tryPair = [&](int a, int b) {
    if (a > 255 || b < 0 || a <= b || (a == e0 && b == e1))
      return;
    uint64_t trial = 0;
    if (float err = fit(a, b, trial); err < best)
      best = err, bits = trial, e0 = a, e1 = b;
  };
  for (int pass = 0; pass < 2 && best > 0; ++pass) {
    // Level i sits at weight w of the way from e0 to e1: 0 for i = 0, 1 for i = 1, (i - 1) / 7.
    double a = 0, b = 0, c = 0, d0 = 0, d1 = 0;
    for (int k = 0; k < 16; ++k) {
      if (!used[k])
        continue;
      int i = int((bits >> (3 * k)) & 7);
      double w = i == 0 ? 0.0 : i == 1 ? 1.0 : (i - 1) / 7.0;
      a += (1 - w) * (1 - w), b += (1 - w) * w, c += w * w;
      d0 += (1 - w) * v[k], d1 += w * v[k];
    }
    double det = a * c - b * b;
    if (std::abs(det) < 1e-9)
      break;
    tryPair(std::clamp(int(std::lround((c * d0 - b * d1) / det)), 0, 255),
            std::clamp(int(std::lround((a * d1 - b * d0) / det)), 0, 255));
  }
  const int f0 = e0, f1 = e1;
  for (int n0 = -1; n0 <= 1; ++n0)
    for (int n1 = -1; n1 <= 1; ++n1)
      tryPair(f0 + n0, f1 + n1);
  out[0] = uint8_t(e0), out[1] = uint8_t(e1);
  for (int k = 0; k < 6; ++k)
    out[2 + k] = uint8_t(bits >> (8 * k));
}

} // namespace

size_t bc5Bytes(uint32_t width, uint32_t height) {
  return size_t((width + 3) / 4) * ((height + 3) / 4) * kBc5BlockBytes;
}

std::vector<uint8_t> encodeBc5(const float *rg, const uint8_t *used, uint32_t width,
                               uint32_t height) {
  std::vector<uint8_t> out(bc5Bytes(width, height), 0);
  const uint32_t bw = (width + 3) / 4, bh = (height + 3) / 4;
  for (uint32_t by = 0; by < bh; ++by)
    for (uint32_t bx = 0; bx < bw; ++bx) {
      float v[2][16] = {};
      bool in[16] = {};
      bool any = false;
      for (uint32_t k = 0; k < 16; ++k) {
        uint32_t x = bx * 4 + k % 4, y = by * 4 + k / 4;
        if (x >= width || y >= height)
          continue;
        size_t i = size_t(y) * width + x;
        in[k] = used[i] != 0;
        any = any || in[k];
        for (int c = 0; c < 2; ++c)
          v[c][k] = std::clamp(rg[i * 2 + size_t(c)], 0.0f, 1.0f) * 255.0f;
      }
      if (!any)
        continue;
      uint8_t *block = &out[(size_t(by) * bw + bx) * kBc5BlockBytes];
      encodeChannel(v[0], in, block);
      encodeChannel(v[1], in, block + 8);
    }
  return out;
}

void decodeBc5(const uint8_t *blocks, uint32_t width, uint32_t height, float *rg) {
  const uint32_t bw = (width + 3) / 4, bh = (height + 3) / 4;
  for (uint32_t by = 0; by < bh; ++by)
    for (uint32_t bx = 0; bx < bw; ++bx) {
      const uint8_t *block = &blocks[(size_t(by) * bw + bx) * kBc5BlockBytes];
      for (int c = 0; c < 2; ++c) {
        const uint8_t *b = block + 8 * c;
        float lv[8];
        levels(b[0], b[1], lv);
        uint64_t bits = 0;
        for (int k = 0; k < 6; ++k)
          bits |= uint64_t(b[2 + k]) << (8 * k);
        for (uint32_t k = 0; k < 16; ++k) {
          uint32_t x = bx * 4 + k % 4, y = by * 4 + k / 4;
          if (x < width && y < height)
            rg[(size_t(y) * width + x) * 2 + size_t(c)] = lv[(bits >> (3 * k)) & 7] / 255.0f;
        }
      }
    }
}

} // namespace crowd::pack
