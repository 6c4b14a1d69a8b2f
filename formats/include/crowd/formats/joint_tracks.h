// Compressed joint animation: per clip, each skeleton node's local rotation, translation and
// scale as tracks sampled at the clip's own times (one time table per clip, so a decoder finds
// any time's two samples without state), each track default (the node's rest value), constant,
// or animated: range-reduced per clip and quantized at its own bit rate. Plain data and the
// bit reads a decoder needs; runtime/track_pose.h decodes poses from it.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace crowd::pack {

inline constexpr uint32_t kMaxTrackBits = 24; // a float's mantissa: more would not be stored
inline constexpr uint32_t kTracksPerNode = 3; // rotation, translation, scale, in that order
// TRAK's version: 2 adds the dropped rotation component (version 1: always w); 3 the time
// table of ticks and extents as halves; 4 constants, ranges' mins and rest values as halves
// where they are halves, and the identity's rest values left out.
inline constexpr uint32_t kJointTracksVersion = 4;
inline constexpr uint32_t kMaxTickBits = 24; // a time table's ticks: a float holds them exactly

enum class TrackKind : uint8_t {
  Default = 0,  // the node's rest value: nothing stored
  Constant = 1, // one value for the whole clip: `min`
  Animated = 2, // a value per sample, `bits` per component
};

// Rotations are stored as three of the unit quaternion's x, y, z, w (in that order), the
// `dropped` one left out and rebuilt >= 0 (sqrt(1 - the others' squares)); translations and
// scales as x, y, z. Constant rotations always drop w.
struct Track {
  TrackKind kind = TrackKind::Default;
  bool step = false; // Animated: each sample holds until the next (glTF STEP); else lerp / slerp
  uint8_t bits = 0;  // Animated: per component, 1..kMaxTrackBits
  // Animated rotations: the component not stored, 0 w, 1 x, 2 y, 3 z. The bake drops the one
  // farthest from 0 over the clip: w rebuilt near 0 amplifies the others' rounding without bound.
  uint8_t dropped = 0;
  // Animated: component c of a sample is min[c] + extent[c] * q / (2^bits - 1), q its stored
  // integer; Constant: min is the value.
  std::array<float, 3> min{}, extent{};
  uint64_t firstBit = 0; // Animated: where its samples start in TrackClip::stream
};

struct TrackClip {
  std::string name;
  // Seconds since the clip's start, non-decreasing, the first 0. Two equal neighbours are a cut:
  // the first ends the interval before it, the second starts the one after.
  std::vector<float> times;
  std::vector<Track> tracks; // kTracksPerNode per node of the TrackSkeleton, node by node
  // Every Animated track's samples one after another, a sample's 3 components `bits` each, low
  // bits first within 32-bit words.
  std::vector<uint32_t> stream;
  float duration() const { return times.empty() ? 0.0f : times.back(); }
};

// The node hierarchy the tracks drive: every ancestor of a joint and the joints themselves.
struct TrackSkeleton {
  std::vector<int32_t> parents; // per node: -1 or an earlier node
  // Per node: its rest rotation (xyzw), translation, scale, or, for a node whose rest transform
  // is a matrix (never animated), 12 floats of that matrix's first three rows.
  std::vector<std::array<float, 12>> rest;
  std::vector<uint8_t> restIsMatrix;
  std::vector<uint32_t> jointNodes; // per joint, its node
  size_t nodeCount() const { return parents.size(); }
};

struct JointTracks {
  TrackSkeleton skeleton;
  std::vector<TrackClip> clips;
};

// `bits` (<= 32) bits of `stream` starting at bit `at`.
uint32_t readBits(const std::vector<uint32_t> &stream, uint64_t at, uint32_t bits);
// Appends `bits` bits of `value` at bit `at` (the stream grows as needed).
void writeBits(std::vector<uint32_t> &stream, uint64_t at, uint32_t bits, uint32_t value);
// An Animated track's sample (its 3 components, dequantized).
std::array<float, 3> trackSample(const TrackClip &clip, const Track &track, uint32_t sample);

// The chunk (TRAK): the skeleton (per node its parent, its rest flags and rest values; per
// joint its node), then per clip its name, sample count, time table (one step where uniformTimes
// holds, else each time's ticks where timeTicks finds a tick and they take fewer bytes, else
// every time as a float), the tracks' kinds (2 bits each), one bit per stored track (its values
// as halves: halfValues), each Constant track's value, each Animated track's bits (low 5 bits;
// bits 5-6 the dropped rotation component; the top bit: step) and range, and the sample stream.
// Little-endian,
// unaligned: docs-grade byte counts, not GPU layout (the player uploads what it decodes).
std::vector<uint8_t> encode(const JointTracks &tracks);
// Checks everything local to the chunk (parents before children, joints' nodes, times
// non-decreasing from 0, kinds, bits, ranges finite, every sample inside the stream).
// Version 1 chunks hold no dropped component (w).
JointTracks decodeJointTracks(std::span<const uint8_t> bytes, const std::string &context,
                              uint32_t version = kJointTracksVersion);
// What a clip takes in the chunk (the skeleton apart: every clip shares it), and the skeleton.
uint64_t clipBytes(const TrackClip &clip);
uint64_t skeletonBytes(const TrackSkeleton &skeleton);
// Whether times[i] is exactly float(i * double(times[1])): then only that step is stored.
bool uniformTimes(const std::vector<float> &times);
// A tick every time is a whole multiple of, each exactly float(n * double(tick)) with n below
// 2^kMaxTickBits, and the bits the largest n takes; {0, 0} where none is found. Times kept from
// a uniform grid, and CUBICSPLINE spans bisected, are such multiples: stored as `bits`-bit
// ticks instead of floats.
struct TimeTicks {
  float tick = 0;
  uint32_t bits = 0;
};
TimeTicks timeTicks(const std::vector<float> &times);
// How the chunk stores a clip's times: one step where uniformTimes holds, else the ticks where
// timeTicks finds some and they take fewer bytes, else every time as a float.
enum class TimeTable : uint8_t { Floats = 0, Step = 1, Ticks = 2 };
TimeTable timeTable(const std::vector<float> &times);
// Whether every extent of an animated track is a binary16 value: then the chunk stores it in 2
// bytes (kind 3 in the chunk's kinds). The bake rounds extents up to halves (a step at most
// 2^-10 coarser).
bool halfExtents(const Track &track);
// Whether every value is a binary16 value (finite, |v| <= 65504, exact): version 4 stores a
// Constant track's value, an Animated track's min, or a node's rest values in 2 bytes each
// where they are. The bake rounds constants and mins to halves where the budget allows.
bool halfValues(std::span<const float> values);

} // namespace crowd::pack
