// The ANIM chunk: joint transforms of every frame as texels, and half floats.
#include "crowd/formats/chunks.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "chunk_checks.h"
#include "crowd/formats/bytes.h"
#include "crowd/formats/error.h"

namespace crowd::pack {

using namespace checks;

const char *name(JointEncoding e) {
  switch (e) {
  case JointEncoding::Matrix3x4:
    return "matrix3x4";
  case JointEncoding::QuatTransScale:
    return "quat_trans_scale";
  case JointEncoding::QtsWithMatrices:
    return "quat_trans_scale_with_matrices";
  }
  return "?";
}
const char *name(TexelFormat f) { return f == TexelFormat::RGBA32F ? "rgba32f" : "rgba16f"; }
uint32_t texelsPerJoint(JointEncoding e) { return e == JointEncoding::Matrix3x4 ? 3 : 2; }
uint32_t bytesPerTexel(TexelFormat f) { return f == TexelFormat::RGBA32F ? 16 : 8; }

bool AnimationTexture::isMatrix(uint32_t joint) const {
  return encoding == JointEncoding::Matrix3x4 ||
         std::binary_search(matrixJoints.begin(), matrixJoints.end(), joint);
}

uint32_t AnimationTexture::frameTexels() const {
  return jointCount * texelsPerJoint(encoding) + uint32_t(matrixJoints.size());
}

std::pair<uint32_t, uint32_t> AnimationTexture::texelOf(uint32_t frame, uint32_t joint) const {
  if (framesPerRow == 0) // a pack of joint tracks alone: sample it through runtime/pack_joints.h
    throw Error("the pack has no animation texture (it stores joint tracks alone)");
  // Each matrix joint before `joint` takes one texel more than the encoding's.
  const auto before = std::lower_bound(matrixJoints.begin(), matrixJoints.end(), joint);
  return {(frame % framesPerRow) * frameTexels() + joint * texelsPerJoint(encoding) +
              uint32_t(before - matrixJoints.begin()),
          frame / framesPerRow};
}

std::array<float, 4> AnimationTexture::texel(uint32_t x, uint32_t y) const {
  std::array<float, 4> out{};
  size_t index = (size_t(y) * width + x) * 4;
  if (format == TexelFormat::RGBA32F) {
    std::memcpy(out.data(), texels.data() + index * 4, 16);
  } else {
    uint16_t h[4];
    std::memcpy(h, texels.data() + index * 2, 8);
    for (int i = 0; i < 4; ++i)
      out[i] = halfToFloat(h[i]);
  }
  return out;
}

std::vector<uint8_t> encode(const AnimationTexture &t) {
  ByteWriter w;
  w.put<uint32_t>(uint32_t(t.encoding));
  w.put<uint32_t>(uint32_t(t.format));
  w.put<uint32_t>(t.width);
  w.put<uint32_t>(t.height);
  w.put<uint32_t>(t.jointCount);
  w.put<uint32_t>(t.framesPerRow);
  w.put<uint32_t>(t.frameCount);
  if (t.encoding == JointEncoding::QtsWithMatrices)
    w.putArray(t.matrixJoints);
  w.putArray(t.texels);
  return w.take();
}

AnimationTexture decodeAnimationTexture(std::span<const uint8_t> bytes,
                                        const std::string &context) {
  ByteReader r(bytes, context);
  AnimationTexture t;
  uint32_t enc = r.get<uint32_t>("encoding");
  if (enc > 2)
    r.fail("encoding", "unknown joint encoding " + std::to_string(enc));
  t.encoding = JointEncoding(enc);
  uint32_t fmt = r.get<uint32_t>("texel format");
  if (fmt > 1)
    r.fail("texel format", "unknown texel format " + std::to_string(fmt));
  t.format = TexelFormat(fmt);
  readSize(r, t.width, t.height, kMaxTextureSide);
  t.jointCount = r.get<uint32_t>("joint count");
  t.framesPerRow = r.get<uint32_t>("frames per row");
  t.frameCount = r.get<uint32_t>("frame count");
  if (t.jointCount == 0 || t.framesPerRow == 0 || t.frameCount == 0)
    r.fail("joint count/frames", "must be non-zero");
  if (t.encoding == JointEncoding::QtsWithMatrices) {
    t.matrixJoints = r.getArray<uint32_t>("matrix joints", t.jointCount);
    if (t.matrixJoints.empty())
      r.fail("matrix joints", "none listed (the encoding is quat_trans_scale then)");
    for (size_t i = 0; i < t.matrixJoints.size(); ++i)
      if (t.matrixJoints[i] >= t.jointCount || (i && t.matrixJoints[i] <= t.matrixJoints[i - 1]))
        r.fail("matrix joints",
               "joint " + std::to_string(t.matrixJoints[i]) + " is out of range or not ascending");
  }
  if (uint64_t(t.framesPerRow) * t.frameTexels() > t.width)
    r.fail("frames per row", "frames do not fit in the texture width");
  if (uint64_t(t.framesPerRow) * t.height < t.frameCount)
    r.fail("frame count", std::to_string(t.frameCount) + " frames do not fit in " +
                              std::to_string(t.height) + " rows");
  uint64_t expected = uint64_t(t.width) * t.height * bytesPerTexel(t.format);
  t.texels = r.getArray<uint8_t>("texels", expected);
  if (t.texels.size() != expected)
    r.fail("texels",
           std::to_string(t.texels.size()) + " bytes, expected " + std::to_string(expected));
  for (uint32_t y = 0; y < t.height; ++y)
    for (uint32_t x = 0; x < t.width; ++x)
      for (float v : t.texel(x, y))
        if (!std::isfinite(v))
          r.fail("texels",
                 "texel (" + std::to_string(x) + ", " + std::to_string(y) + ") is not finite");
  r.expectEnd();
  return t;
}

uint16_t floatToHalf(float f) {
  uint32_t x;
  std::memcpy(&x, &f, 4);
  uint32_t sign = (x >> 16) & 0x8000u;
  uint32_t mag = x & 0x7fffffffu;
  if (mag >= 0x7f800000u)
    return uint16_t(sign | 0x7c00u | (mag > 0x7f800000u ? 0x200u : 0));
  if (mag >= 0x477ff000u)
    return uint16_t(sign | 0x7c00u);    // rounds to >= 65520: infinity
  if (mag < 0x38800000u) {              // subnormal half (or zero)
    uint32_t shift = 126 - (mag >> 23); // the 24-bit mantissa's shift to half subnormal units
    if (shift > 24)
      return uint16_t(sign); // below half the smallest subnormal: zero
    uint32_t mant = (mag & 0x7fffffu) | 0x800000u;
    uint32_t half = mant >> shift;
    uint32_t rem = mant & ((1u << shift) - 1);
    uint32_t mid = 1u << (shift - 1);
    if (rem > mid || (rem == mid && (half & 1)))
      ++half;
    return uint16_t(sign | half);
  }
  uint32_t half = ((mag - 0x38000000u) >> 13);
  uint32_t rem = mag & 0x1fffu;
  if (rem > 0x1000u || (rem == 0x1000u && (half & 1)))
    ++half;
  return uint16_t(sign | half);
}

float halfToFloat(uint16_t h) {
  uint32_t sign = uint32_t(h & 0x8000u) << 16;
  uint32_t exp = (h >> 10) & 0x1fu;
  uint32_t mant = h & 0x3ffu;
  uint32_t x;
  if (exp == 0) {
    if (mant == 0) {
      x = sign;
    } else { // subnormal: normalise
      int e = -1;
      do {
        ++e;
        mant <<= 1;
      } while (!(mant & 0x400u));
      x = sign | uint32_t(127 - 15 - e) << 23 | (mant & 0x3ffu) << 13;
    }
  } else if (exp == 31) {
    x = sign | 0x7f800000u | mant << 13;
  } else {
    x = sign | (exp + 112) << 23 | mant << 13;
  }
  float f;
  std::memcpy(&f, &x, 4);
  return f;
}

} // namespace crowd::pack
