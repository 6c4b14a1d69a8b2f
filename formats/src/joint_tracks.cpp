#include "crowd/formats/joint_tracks.h"

#include <cmath>

#include "crowd/formats/bytes.h"
#include "crowd/formats/chunks.h"
#include "crowd/formats/limits.h"

namespace crowd::pack {

namespace {
constexpr int kTickShares = 4; // a tick is looked for at the smallest gap over 1 .. 4

// A node's rest flags (version 4; versions 1-3 hold the matrix bit alone): the identity's
// rotation, translation or scale left out, and the values stored as halves where all are.
constexpr uint8_t kRestMatrix = 1, kRestHalves = 2, kRestNoRotation = 4, kRestNoTranslation = 8,
                  kRestNoScale = 16;
constexpr uint8_t kRestFlags = 31;
// Where each part of a non-matrix rest lies in TrackSkeleton::rest, and its identity value.
struct RestPart {
  uint8_t flag;
  size_t first, count;
  float identity[4];
};
constexpr RestPart kRestParts[3] = {{kRestNoRotation, 0, 4, {0, 0, 0, 1}},
                                    {kRestNoTranslation, 4, 3, {0, 0, 0, 0}},
                                    {kRestNoScale, 7, 3, {1, 1, 1, 0}}};
} // namespace

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

TimeTicks timeTicks(const std::vector<float> &times) {
  double gap = 0; // the smallest step between two times: one tick or a few
  for (size_t i = 1; i < times.size(); ++i)
    if (const double d = double(times[i]) - double(times[i - 1]); d > 0 && (gap == 0 || d < gap))
      gap = d;
  if (!(gap > 0))
    return {};
  // Per share of the gap (samples dropped on a grid can leave no two neighbours), the last
  // time's whole number of ticks and the floats around its quotient: a grid's step is found to
  // the bit though each time was rounded on its own. The largest tick that holds every time.
  const double last = times.back();
  for (int share = 1; share <= kTickShares; ++share) {
    const double steps = std::round(last / (gap / share));
    if (!(steps >= 1))
      continue;
    float tick = float(last / steps);
    for (int k = 0; k < 3; ++k)
      tick = std::nextafter(tick, 0.0f);
    for (int k = 0; k < 7; ++k, tick = std::nextafter(tick, INFINITY)) {
      uint64_t most = 0;
      bool all = tick > 0;
      for (size_t i = 0; i < times.size() && all; ++i) {
        const double n = std::round(double(times[i]) / double(tick));
        all = n < double(uint64_t(1) << kMaxTickBits) && float(n * double(tick)) == times[i];
        most = std::max(most, uint64_t(n));
      }
      if (all) {
        uint32_t bits = 1;
        while ((most >> bits) != 0)
          ++bits;
        return {tick, bits};
      }
    }
  }
  return {};
}

bool halfExtents(const Track &track) {
  for (float e : track.extent)
    if (!(e >= 0 && e <= 65504.0f) || halfToFloat(floatToHalf(e)) != e)
      return false;
  return true;
}

bool halfValues(std::span<const float> values) {
  for (float v : values)
    if (!(std::abs(v) <= 65504.0f) || halfToFloat(floatToHalf(v)) != v)
      return false;
  return true;
}

TimeTable timeTable(const std::vector<float> &times) {
  if (uniformTimes(times))
    return TimeTable::Step;
  const TimeTicks ticks = timeTicks(times);
  const uint64_t tickBytes = 5 + (uint64_t(times.size()) * ticks.bits + 7) / 8;
  return ticks.bits && tickBytes < 4 * times.size() ? TimeTable::Ticks : TimeTable::Floats;
}

namespace {

// What the chunk says of a track's kind: an animated track whose extents are halves, 3.
uint8_t storedKind(const Track &t) {
  return t.kind == TrackKind::Animated && halfExtents(t) ? 3 : uint8_t(t.kind);
}

void putTimes(ByteWriter &w, const std::vector<float> &times) {
  const TimeTable kind = timeTable(times);
  w.put<uint8_t>(uint8_t(kind));
  if (kind == TimeTable::Step) {
    w.put<float>(times[1]);
    return;
  }
  if (kind == TimeTable::Floats) {
    for (float t : times)
      w.put<float>(t);
    return;
  }
  const TimeTicks ticks = timeTicks(times);
  w.put<float>(ticks.tick);
  w.put<uint8_t>(uint8_t(ticks.bits));
  std::vector<uint32_t> words;
  for (size_t i = 0; i < times.size(); ++i)
    writeBits(words, i * ticks.bits, ticks.bits,
              uint32_t(std::round(double(times[i]) / double(ticks.tick))));
  for (uint64_t b = 0; b < (uint64_t(times.size()) * ticks.bits + 7) / 8; ++b)
    w.put<uint8_t>(uint8_t(words[b / 4] >> (8 * (b % 4))));
}

void putClip(ByteWriter &w, const TrackClip &clip) {
  w.putString(clip.name);
  w.put<uint32_t>(uint32_t(clip.times.size()));
  putTimes(w, clip.times);
  for (size_t t = 0; t < clip.tracks.size(); t += 4) {
    uint8_t kinds = 0;
    for (size_t k = 0; k < 4 && t + k < clip.tracks.size(); ++k)
      kinds = uint8_t(kinds | storedKind(clip.tracks[t + k]) << (2 * k));
    w.put<uint8_t>(kinds);
  }
  std::vector<uint32_t> halves; // per stored track, whether its value or min is halves
  uint64_t stored = 0;
  for (const Track &t : clip.tracks)
    if (t.kind != TrackKind::Default)
      writeBits(halves, stored++, 1, halfValues(t.min));
  for (uint64_t b = 0; b < (stored + 7) / 8; ++b)
    w.put<uint8_t>(uint8_t(halves[b / 4] >> (8 * (b % 4))));
  const auto putValues = [&](const std::array<float, 3> &values) {
    const bool half = halfValues(values);
    for (float v : values)
      half ? w.put<uint16_t>(floatToHalf(v)) : w.put<float>(v);
  };
  for (const Track &t : clip.tracks) {
    if (t.kind == TrackKind::Constant)
      putValues(t.min);
    if (t.kind != TrackKind::Animated)
      continue;
    w.put<uint8_t>(uint8_t(t.bits | t.dropped << 5 | (t.step ? 0x80 : 0)));
    putValues(t.min);
    const bool half = halfExtents(t);
    for (float v : t.extent)
      half ? w.put<uint16_t>(floatToHalf(v)) : w.put<float>(v);
  }
  w.put<uint32_t>(uint32_t(clip.stream.size()));
  for (uint32_t word : clip.stream)
    w.put<uint32_t>(word);
}

void putSkeleton(ByteWriter &w, const TrackSkeleton &s) {
  w.put<uint32_t>(uint32_t(s.nodeCount()));
  for (size_t n = 0; n < s.nodeCount(); ++n) {
    w.put<int32_t>(s.parents[n]);
    const std::array<float, 12> &rest = s.rest[n];
    std::vector<float> values; // what is stored, in order
    uint8_t flags = s.restIsMatrix[n] ? kRestMatrix : 0;
    if (flags)
      values.assign(rest.begin(), rest.end());
    else
      for (const RestPart &part : kRestParts) {
        bool identity = true;
        for (size_t k = 0; k < part.count; ++k)
          identity &= rest[part.first + k] == part.identity[k];
        if (identity)
          flags |= part.flag;
        else
          values.insert(values.end(), rest.begin() + long(part.first),
                        rest.begin() + long(part.first + part.count));
      }
    const bool half = !values.empty() && halfValues(values);
    w.put<uint8_t>(uint8_t(flags | (half ? kRestHalves : 0)));
    for (float v : values)
      half ? w.put<uint16_t>(floatToHalf(v)) : w.put<float>(v);
  }
  w.put<uint32_t>(uint32_t(s.jointNodes.size()));
  for (uint32_t node : s.jointNodes)
    w.put<uint32_t>(node);
}

float finiteFloat(ByteReader &r, const char *field) {
  const float v = r.get<float>(field);
  if (!std::isfinite(v))
    r.fail(field, "a value is NaN or infinite");
  return v;
}

float finiteHalf(ByteReader &r, const char *field) {
  const float v = halfToFloat(r.get<uint16_t>(field));
  if (!std::isfinite(v))
    r.fail(field, "a value is NaN or infinite");
  return v;
}

TrackSkeleton getSkeleton(ByteReader &r, uint32_t version) {
  TrackSkeleton s;
  const uint32_t nodes = r.get<uint32_t>("node count");
  if (nodes == 0 || nodes > limits::kJoints * 2u)
    r.fail("node count",
           std::to_string(nodes) + " is not in 1.." + std::to_string(limits::kJoints * 2u));
  for (uint32_t n = 0; n < nodes; ++n) {
    const int32_t parent = r.get<int32_t>("parents");
    if (parent < -1 || parent >= int32_t(n))
      r.fail("parents", "node " + std::to_string(n) + " has parent " + std::to_string(parent) +
                            " (a parent comes before its children)");
    const uint8_t flags = r.get<uint8_t>("rest flags");
    const bool matrix = flags & kRestMatrix, half = flags & kRestHalves;
    if (flags > (version < 4 ? kRestMatrix : kRestFlags) || (matrix && flags > 3))
      r.fail("rest flags", "node " + std::to_string(n) + ": " + std::to_string(flags));
    std::array<float, 12> rest{};
    const auto get = [&] { return half ? finiteHalf(r, "rest") : finiteFloat(r, "rest"); };
    if (matrix)
      for (float &v : rest)
        v = get();
    else
      for (const RestPart &part : kRestParts)
        for (size_t k = 0; k < part.count; ++k)
          rest[part.first + k] = flags & part.flag ? part.identity[k] : get();
    s.parents.push_back(parent);
    s.restIsMatrix.push_back(matrix);
    s.rest.push_back(rest);
  }
  const uint32_t joints = r.get<uint32_t>("joint count");
  if (joints > limits::kJoints)
    r.fail("joint count", std::to_string(joints) + " exceeds " + std::to_string(limits::kJoints));
  for (uint32_t j = 0; j < joints; ++j) {
    const uint32_t node = r.get<uint32_t>("joint nodes");
    if (node >= nodes)
      r.fail("joint nodes", "joint " + std::to_string(j) + " names node " + std::to_string(node) +
                                " of " + std::to_string(nodes));
    s.jointNodes.push_back(node);
  }
  return s;
}

TrackClip getClip(ByteReader &r, size_t nodes, uint32_t version) {
  TrackClip clip;
  clip.name = r.getString("clip name");
  const std::string where = "clip '" + clip.name + "': ";
  const uint32_t samples = r.get<uint32_t>("sample count");
  if (samples == 0 || samples > limits::kTrackSamples)
    r.fail("sample count", where + std::to_string(samples) + " is not in 1.." +
                               std::to_string(limits::kTrackSamples));
  const uint8_t table = r.get<uint8_t>("time table");
  if (table > (version < 3 ? 1 : 2) || (table && samples < 2))
    r.fail("time table", where + "kind " + std::to_string(table) + " for " +
                             std::to_string(samples) + " samples");
  if (table) {
    const float step = finiteFloat(r, table == 1 ? "time step" : "time tick");
    if (!(step > 0))
      r.fail(table == 1 ? "time step" : "time tick", where + "not positive");
    std::vector<uint32_t> ticks;
    uint32_t bits = 0;
    if (table == 2) {
      bits = r.get<uint8_t>("tick bits");
      if (bits == 0 || bits > kMaxTickBits)
        r.fail("tick bits",
               where + std::to_string(bits) + " (1.." + std::to_string(kMaxTickBits) + ")");
      ticks.resize((uint64_t(samples) * bits + 31) / 32);
      for (uint64_t b = 0; b < (uint64_t(samples) * bits + 7) / 8; ++b)
        ticks[b / 4] |= uint32_t(r.get<uint8_t>("ticks")) << (8 * (b % 4));
    }
    for (uint32_t i = 0; i < samples; ++i)
      clip.times.push_back(
          float(double(table == 1 ? i : readBits(ticks, uint64_t(i) * bits, bits)) * double(step)));
  } else
    for (uint32_t i = 0; i < samples; ++i)
      clip.times.push_back(finiteFloat(r, "times"));
  for (uint32_t i = 0; i < samples; ++i)
    if (i ? clip.times[i] < clip.times[i - 1] : clip.times[0] != 0)
      r.fail("times", where + "sample " + std::to_string(i) + " at " +
                          std::to_string(clip.times[i]) +
                          (i ? " is before the one before it" : " (the first is at 0)"));
  const size_t tracks = nodes * kTracksPerNode;
  clip.tracks.resize(tracks);
  std::vector<uint8_t> halfExtent(tracks, 0); // kind 3: animated, extents as halves
  for (size_t t = 0; t < tracks; t += 4) {
    const uint8_t kinds = r.get<uint8_t>("track kinds");
    for (size_t k = 0; k < 4 && t + k < tracks; ++k) {
      const uint8_t kind = (kinds >> (2 * k)) & 3;
      if (kind == 3 && version < 3)
        r.fail("track kinds", where + "track " + std::to_string(t + k) +
                                  " has kind 3 (animated with half extents: version 3)");
      halfExtent[t + k] = kind == 3;
      clip.tracks[t + k].kind = kind == 3 ? TrackKind::Animated : TrackKind(kind);
    }
  }
  std::vector<uint8_t> halves(tracks, 0); // version 4: a stored track's value or min as halves
  if (version >= 4) {
    std::vector<size_t> stored;
    for (size_t t = 0; t < tracks; ++t)
      if (clip.tracks[t].kind != TrackKind::Default)
        stored.push_back(t);
    for (size_t b = 0; b < (stored.size() + 7) / 8; ++b) {
      const uint8_t byte = r.get<uint8_t>("half values");
      for (size_t k = 0; k < 8; ++k)
        if (byte >> k & 1) {
          if (b * 8 + k >= stored.size())
            r.fail("half values", where + "a bit past the " + std::to_string(stored.size()) +
                                      " stored tracks is set");
          halves[stored[b * 8 + k]] = 1;
        }
    }
  }
  const auto getValues = [&](std::array<float, 3> &values, size_t t, const char *field) {
    for (float &v : values)
      v = halves[t] ? finiteHalf(r, field) : finiteFloat(r, field);
  };
  uint64_t bits = 0;
  for (size_t t = 0; t < tracks; ++t) {
    Track &track = clip.tracks[t];
    if (track.kind == TrackKind::Constant)
      getValues(track.min, t, "constant value");
    if (track.kind != TrackKind::Animated)
      continue;
    const uint8_t b = r.get<uint8_t>("bits");
    track.step = b & 0x80;
    track.bits = b & 0x1f;
    track.dropped = (b >> 5) & 3;
    if (track.dropped && (version < 2 || t % kTracksPerNode != 0))
      r.fail("bits", where + "track " + std::to_string(t) + " drops component " +
                         std::to_string(track.dropped) +
                         (version < 2 ? " (version 1 drops w)" : " (not a rotation)"));
    if (track.bits == 0 || track.bits > kMaxTrackBits)
      r.fail("bits", where + "track " + std::to_string(t) + " has " + std::to_string(track.bits) +
                         " bits (1.." + std::to_string(kMaxTrackBits) + ")");
    getValues(track.min, t, "range");
    for (float &v : track.extent) {
      v = halfExtent[t] ? halfToFloat(r.get<uint16_t>("range")) : finiteFloat(r, "range");
      if (!std::isfinite(v))
        r.fail("range", where + "track " + std::to_string(t) + " has an extent NaN or infinite");
      if (v < 0)
        r.fail("range", where + "track " + std::to_string(t) + " has a negative extent");
    }
    track.firstBit = bits;
    bits += uint64_t(samples) * 3 * track.bits;
  }
  const uint32_t words = r.get<uint32_t>("stream");
  if (uint64_t(words) * 32 < bits || uint64_t(words) > (bits + 31) / 32)
    r.fail("stream", where + std::to_string(words) + " words for " + std::to_string(bits) +
                         " bits of samples");
  clip.stream.resize(words);
  for (uint32_t &word : clip.stream)
    word = r.get<uint32_t>("stream");
  return clip;
}

} // namespace

std::vector<uint8_t> encode(const JointTracks &tracks) {
  ByteWriter w;
  putSkeleton(w, tracks.skeleton);
  w.put<uint32_t>(uint32_t(tracks.clips.size()));
  for (const TrackClip &clip : tracks.clips)
    putClip(w, clip);
  return w.take();
}

JointTracks decodeJointTracks(std::span<const uint8_t> bytes, const std::string &context,
                              uint32_t version) {
  ByteReader r(bytes, context);
  JointTracks out;
  out.skeleton = getSkeleton(r, version);
  const uint32_t clips = r.get<uint32_t>("clip count");
  if (clips > bytes.size()) // a clip takes at least 10 bytes
    r.fail("clip count",
           std::to_string(clips) + " clips in " + std::to_string(bytes.size()) + " bytes");
  for (uint32_t c = 0; c < clips; ++c)
    out.clips.push_back(getClip(r, out.skeleton.nodeCount(), version));
  r.expectEnd();
  return out;
}

uint64_t clipBytes(const TrackClip &clip) {
  ByteWriter w;
  putClip(w, clip);
  return w.take().size();
}

uint64_t skeletonBytes(const TrackSkeleton &s) {
  ByteWriter w;
  putSkeleton(w, s);
  return w.take().size();
}

} // namespace crowd::pack
