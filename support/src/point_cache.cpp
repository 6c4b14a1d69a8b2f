#include "crowd/support/point_cache.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "crowd/formats/error.h"
#include "crowd/formats/limits.h"

namespace crowd {

namespace {

constexpr char kPc2Magic[12] = {'P', 'O', 'I', 'N', 'T', 'C', 'A', 'C', 'H', 'E', '2', '\0'};
constexpr uint64_t kPc2Header = 32;

uint32_t swap32(uint32_t v) {
  return (v >> 24) | ((v >> 8) & 0xff00u) | ((v << 8) & 0xff0000u) | (v << 24);
}

// A 32-bit field at `at` of `bytes`, little- or big-endian.
uint32_t word(const uint8_t *bytes, bool big) {
  uint32_t v;
  std::memcpy(&v, bytes, 4);
  return big ? swap32(v) : v;
}
float real(const uint8_t *bytes, bool big) { return std::bit_cast<float>(word(bytes, big)); }

bool endsWith(const std::string &s, const char *tail) {
  const size_t n = std::strlen(tail);
  return s.size() >= n && s.compare(s.size() - n, n, tail) == 0;
}

} // namespace

PointCacheReader::PointCacheReader(const std::string &path, const FileBound &bound) : path_(path) {
  const uint64_t size = checkRegularFile(path, bound);
  in_.open(path, std::ios::binary);
  if (!in_)
    throw Error(path + ": cannot open the point cache");
  uint8_t head[32] = {};
  in_.read(reinterpret_cast<char *>(head), std::streamsize(std::min<uint64_t>(size, 32)));
  in_.clear(); // a file shorter than 32 bytes (a small MDD) ends the read early: not an error
  const bool pc2 = size >= 12 && std::memcmp(head, kPc2Magic, 12) == 0;
  if (!pc2 && endsWith(path, ".pc2"))
    throw Error(path + ": not a PC2 file (no POINTCACHE2 header)");
  info_.format = pc2 ? PointCacheFormat::Pc2 : PointCacheFormat::Mdd;
  uint64_t frames = 0;
  if (pc2) {
    if (size < kPc2Header)
      throw Error(path + ": PC2 header is " + std::to_string(size) + " bytes, needs 32");
    if (const uint32_t version = word(head + 12, false); version != 1)
      throw Error(path + ": PC2 version " + std::to_string(version) + ", only 1 is known");
    info_.vertexCount = word(head + 16, false);
    info_.startFrame = real(head + 20, false);
    const float step = real(head + 24, false);
    frames = word(head + 28, false);
    if (!std::isfinite(info_.startFrame) || !(step > 0.0f) || !std::isfinite(step))
      throw Error(path + ": PC2 start frame " + std::to_string(info_.startFrame) +
                  " or sample step " + std::to_string(step) + " is not a finite, positive step");
    info_.dataOffset = kPc2Header;
  } else {
    if (size < 8)
      throw Error(path + ": MDD header is " + std::to_string(size) + " bytes, needs 8");
    frames = word(head, true);
    info_.vertexCount = word(head + 4, true);
    info_.dataOffset = 8 + 4 * frames;
  }
  const char *name = pc2 ? "PC2" : "MDD";
  if (frames == 0 || frames > limits::kCacheFrames)
    throw Error(path + ": " + name + " header says " + std::to_string(frames) + " frames (1 to " +
                std::to_string(limits::kCacheFrames) + " allowed)");
  if (info_.vertexCount == 0 || info_.vertexCount > limits::kVertices)
    throw Error(path + ": " + name + " header says " + std::to_string(info_.vertexCount) +
                " vertices (1 to " + std::to_string(limits::kVertices) + " allowed)");
  info_.frameCount = uint32_t(frames);
  const uint64_t expected = info_.dataOffset + frames * info_.vertexCount * 12;
  if (size != expected)
    throw Error(path + ": " + name + " header says " + std::to_string(frames) + " frames of " +
                std::to_string(info_.vertexCount) + " vertices (" + std::to_string(expected) +
                " bytes), but the file holds " + std::to_string(size) + " bytes" +
                (size < expected ? " (truncated?)" : ""));
  if (!pc2) { // times: finite, increasing, uniform
    std::vector<uint8_t> times(4 * frames);
    in_.seekg(8);
    in_.read(reinterpret_cast<char *>(times.data()), std::streamsize(times.size()));
    if (!in_)
      throw Error(path + ": cannot read the MDD frame times");
    const double t0 = real(times.data(), true);
    if (!std::isfinite(t0))
      throw Error(path + ": MDD time of frame 0 is not finite");
    if (frames > 1) {
      const double step = double(real(times.data() + 4, true)) - t0;
      for (uint64_t f = 1; f < frames; ++f) {
        const double t = real(times.data() + 4 * f, true);
        const double prev = real(times.data() + 4 * (f - 1), true);
        if (!std::isfinite(t) || !(step > 0.0) || std::abs((t - prev) - step) > 1e-3 * step)
          throw Error(path + ": MDD time of frame " + std::to_string(f) + " (" + std::to_string(t) +
                      " s) breaks the uniform step of " + std::to_string(step) +
                      " s; resample the cache to a fixed frame rate");
      }
      // The mean step over the whole cache (float times round each step), and whole rates
      // exactly (30, not 29.9999995).
      const double last = real(times.data() + 4 * (frames - 1), true);
      info_.fps = double(frames - 1) / (last - t0);
      if (std::abs(info_.fps - std::round(info_.fps)) < 1e-5 * info_.fps)
        info_.fps = std::round(info_.fps);
      info_.startFrame = t0 * info_.fps;
    }
  }
}

void PointCacheReader::read(uint32_t frame, uint32_t first, uint32_t count,
                            std::vector<glm::vec3> &out) {
  if (frame >= info_.frameCount || first > info_.vertexCount || count > info_.vertexCount - first)
    throw Error(path_ + ": frame " + std::to_string(frame) + " vertices " + std::to_string(first) +
                "+" + std::to_string(count) + " are outside the cache");
  raw_.resize(size_t(count) * 12);
  in_.seekg(std::streamoff(info_.dataOffset + (uint64_t(frame) * info_.vertexCount + first) * 12));
  in_.read(reinterpret_cast<char *>(raw_.data()), std::streamsize(raw_.size()));
  if (!in_)
    throw Error(path_ + ": cannot read frame " + std::to_string(frame) +
                " (the file changed while it was read?)");
  const bool big = info_.format == PointCacheFormat::Mdd;
  out.resize(count);
  for (uint32_t v = 0; v < count; ++v) {
    const uint8_t *p = raw_.data() + size_t(v) * 12;
    out[v] = {real(p, big), real(p + 4, big), real(p + 8, big)};
    if (!std::isfinite(out[v].x) || !std::isfinite(out[v].y) || !std::isfinite(out[v].z))
      throw Error(path_ + ": frame " + std::to_string(frame) + ", vertex " +
                  std::to_string(first + v) + ": position is not finite (NaN or infinite)");
  }
}

std::vector<uint8_t> encodePointCache(PointCacheFormat format,
                                      const std::vector<std::vector<glm::vec3>> &frames, double fps,
                                      float pc2Start, float pc2Step) {
  const bool big = format == PointCacheFormat::Mdd;
  const uint32_t vertices = frames.empty() ? 0 : uint32_t(frames[0].size());
  std::vector<uint8_t> out;
  auto put = [&](uint32_t v) {
    for (int i = 0; i < 4; ++i)
      out.push_back(uint8_t(v >> (big ? 24 - 8 * i : 8 * i)));
  };
  auto putReal = [&](float f) { put(std::bit_cast<uint32_t>(f)); };
  if (big) {
    put(uint32_t(frames.size()));
    put(vertices);
    for (size_t f = 0; f < frames.size(); ++f)
      putReal(float(double(f) / fps));
  } else {
    out.assign(kPc2Magic, kPc2Magic + 12);
    put(1);
    put(vertices);
    putReal(pc2Start);
    putReal(pc2Step);
    put(uint32_t(frames.size()));
  }
  for (const auto &frame : frames) {
    if (frame.size() != vertices)
      throw Error("point cache: every frame needs " + std::to_string(vertices) + " vertices");
    for (const auto &p : frame) {
      putReal(p.x);
      putReal(p.y);
      putReal(p.z);
    }
  }
  return out;
}

} // namespace crowd
