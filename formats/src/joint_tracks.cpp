#include "crowd/formats/joint_tracks.h"

namespace crowd::pack {

uint32_t readBits(const std::vector<uint32_t> &stream, uint64_t at, uint32_t bits) {
  if (bits == 0)
    return 0;
  const uint64_t word = at / 32, shift = at % 32;
  uint64_t v = stream[word] >> shift;
  if (shift + bits > 32)
    v |= uint64_t(stream[word + 1]) << (32 - shift);
  return uint32_t(v & ((uint64_t(1) << bits) - 1));
}

void writeBits(std::vector<uint32_t> &stream, uint64_t at, uint32_t bits, uint32_t value) {
  if (bits == 0)
    return;
  const uint64_t last = (at + bits - 1) / 32;
  if (stream.size() <= last)
    stream.resize(last + 1, 0);
  const uint64_t word = at / 32, shift = at % 32;
  const uint64_t mask = (uint64_t(1) << bits) - 1;
  const uint64_t v = uint64_t(value) & mask;
  stream[word] = uint32_t((stream[word] & ~(mask << shift)) | (v << shift));
  if (shift + bits > 32) {
    const uint64_t high = mask >> (32 - shift);
    stream[word + 1] = uint32_t((stream[word + 1] & ~high) | (v >> (32 - shift)));
  }
}

std::array<float, 3> trackSample(const TrackClip &clip, const Track &track, uint32_t sample) {
  const uint32_t b = track.bits;
  const float top = float((uint64_t(1) << b) - 1);
  std::array<float, 3> out;
  uint64_t at = track.firstBit + uint64_t(sample) * 3 * b;
  for (int c = 0; c < 3; ++c, at += b)
    out[size_t(c)] = track.min[size_t(c)] +
                     track.extent[size_t(c)] * (float(readBits(clip.stream, at, b)) / top);
  return out;
}

bool uniformTimes(const std::vector<float> &times) {
  if (times.size() < 2 || !(times[1] > 0))
    return false;
  const double step = times[1];
  for (size_t i = 0; i < times.size(); ++i)
    if (times[i] != float(double(i) * step))
      return false;
  return true;
}

uint64_t clipBytes(const TrackClip &clip) {
  uint64_t bytes = 4 + clip.name.size(); // length-prefixed name
  bytes += 4 + 1;                        // sample count, time-table kind
  bytes += uniformTimes(clip.times) ? 4 : 4 * clip.times.size();
  bytes += (clip.tracks.size() * 2 + 7) / 8; // kinds, 2 bits each
  for (const Track &t : clip.tracks)
    if (t.kind == TrackKind::Constant)
      bytes += 12;
    else if (t.kind == TrackKind::Animated)
      bytes += 1 + 24; // bits and the step flag; min and extent
  return bytes + 4 * clip.stream.size();
}

uint64_t skeletonBytes(const TrackSkeleton &s) {
  uint64_t bytes = 4 + 4 * s.parents.size() + 4 * s.jointNodes.size();
  for (size_t n = 0; n < s.rest.size(); ++n)
    bytes += 1 + (s.restIsMatrix[n] ? 48 : 40);
  return bytes;
}

} // namespace crowd::pack
