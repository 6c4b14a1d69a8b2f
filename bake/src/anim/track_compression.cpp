#include "crowd/bake/track_compression.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>

#include "crowd/bake/anim_frames.h"
#include "crowd/bake/evaluate.h"
#include "crowd/bake/parallel.h"
#include "crowd/formats/error.h"
#include "crowd/formats/limits.h"
#include "crowd/runtime/texture_skinning.h"
#include "crowd/runtime/track_pose.h"
#include "skin_error_bound.h"

namespace crowd {
namespace {

// Animated tracks start here and rise a bit at a time: fewer bits rarely hold a joint that moves.
constexpr uint32_t kFirstBits = 1;
// Share of the budget the joints' boxes may take at the samples: the rest is left to the
// interpolation between them and to single precision, which only the vertex measure sees.
constexpr double kSampleShare = 0.9;
// Share of the budget the joints' boxes may err by at a dropped sample, interpolated from the
// kept ones with exact values. The boxes bound the vertices' error from above, so the two shares
// add to more than the whole; the vertex measure has the last word. Over the shared models
// (track_bench) 0.7 took the fewest bytes of 0.2-1.2 with every clip within 1 mm; at 0.9, dq's
// CUBICSPLINE clips missed it (1.02 mm).
constexpr double kDropShare = 0.7;
// Share the tracks turned constant may take together, before bits are allotted.
constexpr double kConstantShare = 0.25;
// Bisections of one span between keys where a CUBICSPLINE channel curves.
constexpr int kMaxSplits = 10;
// Samples dropSamples may bridge at most (a bound on its search).
constexpr size_t kMaxDropSpan = 32;
// Bits ahead a raise looks (raiseFor).
constexpr uint32_t kRaiseLookahead = 3;
// Where no raise lowers a joint's error, its chain's coarsest track still rises to this many
// bits (two tracks' errors can cancel at few bits); past it the joint is at its floor.
constexpr uint32_t kFloorBits = 16;
// Rounds of tightening the joints' tolerance where the vertex measure misses the budget.
constexpr int kTighteningRounds = 8;
// Node or corner transforms a loop needs before it is shared between threads. A raise of
// RecursiveSkeletons' 1,000 nodes at 3 samples took 3.5x longer on two threads than on one;
// from 1,000 to 64,000 the bakes of the shared models took the same time within 10%.
constexpr size_t kSharedWork = 8000;
// Key times within this share of a step of a uniform grid are stored as the grid.
constexpr double kUniformSlack = 1e-5;
// An animated track's min is a half (2 bytes in the chunk, not 4) where rounding it down to one
// widens the range by at most this share of it. Over the shared models (track_bench) 1/16 took
// the fewest bytes of 0, 1/512, 1/128, 1/32, 1/16 and 1/8.
constexpr double kHalfMinWidening = 1.0 / 16;

glm::dmat4 trsMatrix(const glm::dquat &r, const glm::dvec3 &t, const glm::dvec3 &s) {
  glm::dmat4 m = glm::mat4_cast(r);
  for (int col = 0; col < 3; ++col)
    m[col] *= s[col];
  m[3] = glm::dvec4(t, 1.0);
  return m;
}

// Quaternion components in the order x, y, z, w; `dropped` (0 w, 1 x, 2 y, 3 z) as an index.
size_t droppedIndex(uint32_t dropped) { return dropped == 0 ? 3 : dropped - 1; }

glm::dquat rotationOf(const std::array<float, 3> &stored, uint32_t dropped) {
  const double a = stored[0], b = stored[1], c = stored[2];
  double xyzw[4];
  const size_t missing = droppedIndex(dropped);
  for (size_t i = 0, k = 0; i < 4; ++i)
    xyzw[i] =
        i == missing ? std::sqrt(std::max(0.0, 1.0 - a * a - b * b - c * c)) : double(stored[k++]);
  return glm::normalize(glm::dquat(xyzw[3], xyzw[0], xyzw[1], xyzw[2]));
}

// The three components of q kept where `dropped` is rebuilt, q's sign chosen so that it is >= 0.
std::array<double, 3> storedRotation(glm::dquat q, uint32_t dropped) {
  const double xyzw[4] = {q.x, q.y, q.z, q.w};
  const size_t missing = droppedIndex(dropped);
  const double sign = xyzw[missing] < 0 ? -1.0 : 1.0;
  std::array<double, 3> out{};
  for (size_t i = 0, k = 0; i < 4; ++i)
    if (i != missing)
      out[k++] = sign * xyzw[i];
  return out;
}

// The largest binary16 value at most v (|v| <= 65504).
float halfAtMost(double v) {
  uint16_t h = pack::floatToHalf(float(v));
  while (double(pack::halfToFloat(h)) > v) // one half down: negative halves grow with their bits
    h = h & 0x8000 ? uint16_t(h + 1) : h == 0 ? uint16_t(0x8001) : uint16_t(h - 1);
  return pack::halfToFloat(h);
}

// The range a float min and extent cover: min rounded down, extent up, so both ends are inside.
// The min is a half where kHalfMinWidening allows, and the extent is rounded up to a half where
// it is a normal one (a step at most 2^-10 coarser): 2 bytes each in the chunk instead of 4
// (pack::halfValues, pack::halfExtents).
void floatRange(double lo, double hi, float &min, float &extent) {
  min = float(lo);
  if (double(min) > lo)
    min = std::nextafter(min, -INFINITY);
  if (std::abs(lo) < 65504.0)
    if (const float h = halfAtMost(lo); lo - double(h) <= kHalfMinWidening * (hi - lo))
      min = h;
  extent = float(hi - double(min));
  while (double(min) + double(extent) < hi)
    extent = std::nextafter(extent, INFINITY);
  if (extent >= 6.103515625e-05f && extent <= 65504.0f) { // 2^-14, the largest half
    uint16_t h = pack::floatToHalf(extent);
    if (pack::halfToFloat(h) < extent)
      ++h; // the next half up: positive halves order as their bits
    if (pack::halfToFloat(h) <= 65504.0f)
      extent = pack::halfToFloat(h);
  }
}

float dequantize(float min, float extent, uint32_t q, uint32_t bits) {
  const float top = float((uint64_t(1) << bits) - 1);
  return min + extent * (float(q) / top);
}

uint32_t quantize(double v, float min, float extent, uint32_t bits) {
  const double top = double((uint64_t(1) << bits) - 1);
  if (!(extent > 0))
    return 0;
  const double q = std::round((v - double(min)) / double(extent) * top);
  return uint32_t(std::clamp(q, 0.0, top));
}

class ClipCompressor {
public:
  ClipCompressor(const Character &c, const TrackRig &rig, const AnimationClip &clip,
                 double tolerance, int threads)
      : c_(c), rig_(rig), clip_(clip), tolerance_(tolerance), threads_(threads),
        nodes_(rig.skeleton.nodeCount()) {
    checkFinite();
    mapChannels();
    buildShells();
    buildTimes();
  }

  uint32_t keys() const { return keys_; }

  // Samples added where CUBICSPLINE spans curve away from linear interpolation.
  void refineCurves() {
    bool curved = false;
    for (const Channel *ch : channelOf_)
      curved |= ch && ch->interpolation == Interpolation::CubicSpline;
    if (!curved)
      return;
    Samples out{{times_.front()}, {sampleAt_.front()}, {fromLeft_.front()}};
    for (size_t i = 0; i + 1 < times_.size(); ++i) {
      if (sampleAt_[i + 1] > sampleAt_[i])
        split(sampleAt_[i], sampleAt_[i + 1], 0, out);
      out.times.push_back(times_[i + 1]);
      out.at.push_back(sampleAt_[i + 1]);
      out.left.push_back(fromLeft_[i + 1]);
    }
    times_ = std::move(out.times);
    sampleAt_ = std::move(out.at);
    fromLeft_ = std::move(out.left);
  }

  // Samples that interpolation between the kept ones reproduces within `share` of the tolerance
  // (over every joint's box, exact values) are dropped, left to right, each kept sample as far
  // from the last as that allows (at most kMaxDropSpan apart); the ends and both samples of a
  // cut stay. The dropped samples' times stay in sampleTimes() for the vertex measure.
  void dropSamples(double share) {
    const size_t n = times_.size();
    allSampleAt_ = sampleAt_;
    if (n < 3 || share <= 0)
      return;
    std::vector<std::vector<Trs>> poses(n);
    std::vector<std::vector<glm::dmat4>> exact(n);
    parallelFor(n, threads_, [&](size_t s) {
      poses[s] = exactPose(sampleAt_[s], fromLeft_[s]);
      exact[s] = globals(poses[s]);
    });
    std::vector<uint8_t> keep(n, 0);
    keep[0] = keep[n - 1] = 1;
    for (size_t i = 0; i + 1 < n; ++i)
      if (times_[i + 1] == times_[i])
        keep[i] = keep[i + 1] = 1;
    const double limit = share * tolerance_;
    const auto reproduces = [&](size_t a, size_t b) {
      for (size_t i = a + 1; i < b; ++i) {
        const double alpha = (times_[i] - times_[a]) / (times_[b] - times_[a]);
        if (poseError(globals(mixPoses(poses[a], poses[b], alpha)), exact[i]) > limit)
          return false;
      }
      return true;
    };
    std::vector<size_t> kept = {0};
    for (size_t a = 0; a + 1 < n;) {
      size_t b = a + 1;
      while (!keep[b] && b + 1 < n && b + 1 - a <= kMaxDropSpan && reproduces(a, b + 1))
        ++b;
      kept.push_back(b);
      a = b;
    }
    if (kept.size() == n)
      return;
    std::vector<double> times, at;
    std::vector<uint8_t> left;
    for (size_t k : kept) {
      times.push_back(times_[k]);
      at.push_back(sampleAt_[k]);
      left.push_back(fromLeft_[k]);
    }
    times_ = std::move(times);
    sampleAt_ = std::move(at);
    fromLeft_ = std::move(left);
  }

  // The exact values at the samples, each track's kind, and the lossless start.
  void sampleTracks() {
    const size_t n = times_.size();
    exact_.assign(nodes_ * 3, std::vector<std::array<double, 3>>(n));
    exactGlobals_.assign(n, std::vector<glm::dmat4>(nodes_));
    std::vector<std::vector<Trs>> poses(n);
    parallelFor(n, threads_, [&](size_t s) {
      poses[s] = exactPose(sampleAt_[s], fromLeft_[s]);
      exactGlobals_[s] = globals(poses[s]);
    });
    rotations_.assign(nodes_, std::vector<glm::dquat>(n));
    for (size_t s = 0; s < n; ++s)
      for (size_t k = 0; k < nodes_; ++k) {
        rotations_[k][s] = poses[s][k].r;
        exact_[k * 3 + 0][s] = storedRotation(poses[s][k].r, 0);
        exact_[k * 3 + 1][s] = {poses[s][k].t.x, poses[s][k].t.y, poses[s][k].t.z};
        exact_[k * 3 + 2][s] = {poses[s][k].s.x, poses[s][k].s.y, poses[s][k].s.z};
      }
    tracks_.assign(nodes_ * 3, {});
    deq_.assign(nodes_ * 3, {});
    for (size_t t = 0; t < nodes_ * 3; ++t)
      classify(t);
    local_.assign(n, std::vector<glm::dmat4>(nodes_));
    global_.assign(n, std::vector<glm::dmat4>(nodes_));
    for (size_t k = 0; k < nodes_; ++k)
      updateLocal(k);
    updateGlobals(kEveryNode);
  }

  // Animated tracks that can be constant within a share of the budget become so.
  void makeConstant() {
    const double limit = kConstantShare * tolerance_;
    for (size_t t = 0; t < tracks_.size(); ++t) {
      if (tracks_[t].kind != pack::TrackKind::Animated)
        continue;
      const pack::Track before = tracks_[t];
      const auto beforeValues = deq_[t];
      pack::Track &track = tracks_[t];
      std::array<double, 3> mid;
      for (int c = 0; c < 3; ++c)
        mid[size_t(c)] = double(track.min[size_t(c)]) + 0.5 * double(track.extent[size_t(c)]);
      if (t % 3 == 0) { // a rotation: the middle of the box, back on the sphere, w dropped
        const std::array<float, 3> m = {float(mid[0]), float(mid[1]), float(mid[2])};
        mid = storedRotation(rotationOf(m, track.dropped), 0);
        track.dropped = 0;
      }
      track.kind = pack::TrackKind::Constant;
      track.bits = 0;
      track.extent = {};
      for (int c = 0; c < 3; ++c)
        track.min[size_t(c)] = float(mid[size_t(c)]);
      deq_[t].assign(times_.size(), track.min);
      if (!commitWithin(t / 3, limit)) {
        track = before;
        deq_[t] = beforeValues;
        commitWithin(t / 3, INFINITY);
      }
    }
  }

  // Constant tracks rounded to halves (2 bytes a value in the chunk, not 4: pack::halfValues)
  // where every joint's box stays within the constants' share of the budget.
  void halveConstants() {
    const double limit = kConstantShare * tolerance_;
    for (size_t t = 0; t < tracks_.size(); ++t) {
      pack::Track &track = tracks_[t];
      if (track.kind != pack::TrackKind::Constant || pack::halfValues(track.min))
        continue;
      const std::array<float, 3> before = track.min;
      for (float &v : track.min)
        v = pack::halfToFloat(pack::floatToHalf(v));
      if (!pack::halfValues(track.min)) { // out of the halves' range
        track.min = before;
        continue;
      }
      deq_[t].assign(times_.size(), track.min);
      if (!commitWithin(t / 3, limit)) {
        track.min = before;
        deq_[t].assign(times_.size(), before);
        commitWithin(t / 3, INFINITY);
      }
    }
  }

  // Every animated track from kFirstBits, raised until each joint's box errs within `share` of
  // the tolerance at every sample.
  void allotBits(double share) {
    const double limit = share * tolerance_;
    for (size_t t = 0; t < tracks_.size(); ++t)
      if (tracks_[t].kind == pack::TrackKind::Animated && tracks_[t].bits == 0) {
        setBits(t, kFirstBits);
      }
    for (size_t k = 0; k < nodes_; ++k)
      updateLocal(k);
    updateGlobals(kEveryNode);
    // Joints no raise lowers (the floor of float and of w rebuilt near 0): the vertex measure
    // judges them; more bits up their chain would buy nothing.
    std::vector<uint8_t> floored(jointError_.size(), 0);
    for (;;) {
      size_t worst = SIZE_MAX;
      double worstError = limit;
      for (size_t j = 0; j < jointError_.size(); ++j)
        if (!floored[j] && jointError_[j] > worstError)
          worst = j, worstError = jointError_[j];
      if (worst == SIZE_MAX)
        return;
      if (!raiseFor(worst, limit))
        floored[worst] = 1;
    }
  }

  const std::vector<double> &times() const { return times_; }
  // Every sample's time before dropSamples: where the vertex measure looks first.
  const std::vector<double> &sampleTimes() const { return allSampleAt_; }

  pack::TrackClip build() const {
    pack::TrackClip out;
    out.name = clip_.name;
    out.times.reserve(times_.size());
    for (double t : times_)
      out.times.push_back(float(t));
    out.tracks = tracks_;
    uint64_t at = 0;
    for (size_t t = 0; t < out.tracks.size(); ++t) {
      pack::Track &track = out.tracks[t];
      if (track.kind != pack::TrackKind::Animated)
        continue;
      track.firstBit = at;
      for (size_t s = 0; s < times_.size(); ++s)
        for (int c = 0; c < 3; ++c, at += track.bits)
          pack::writeBits(out.stream, at, track.bits,
                          quantize(exact_[t][s][size_t(c)], track.min[size_t(c)],
                                   track.extent[size_t(c)], track.bits));
    }
    return out;
  }

private:
  struct Trs {
    glm::dquat r;
    glm::dvec3 t, s;
  };

  void checkFinite() const {
    for (const Channel &ch : clip_.channels)
      for (size_t i = 0; i < ch.values.size(); ++i)
        if (!std::isfinite(ch.values[i]))
          throw Error("clip '" + clip_.name + "': node '" + c_.nodes[size_t(ch.node)].name +
                      "': key " + std::to_string(i / std::max<size_t>(ch.components, 1)) +
                      " is NaN or infinite");
  }

  void mapChannels() {
    std::vector<int> index(c_.nodes.size(), -1);
    for (size_t k = 0; k < nodes_; ++k)
      index[size_t(rig_.sourceNode[k])] = int(k);
    channelOf_.assign(nodes_ * 3, nullptr);
    for (const Channel &ch : clip_.channels) {
      if (ch.path == ChannelPath::Weights || index[size_t(ch.node)] < 0)
        continue;
      const size_t p = ch.path == ChannelPath::Rotation      ? 0
                       : ch.path == ChannelPath::Translation ? 1
                                                             : 2;
      channelOf_[size_t(index[size_t(ch.node)]) * 3 + p] = &ch;
    }
  }

  // Per joint, the corners of the bind-pose box of the vertices it moves, in the joint's frame:
  // the largest error of an affine map over the box is at one of them.
  void buildShells() {
    const SkinnedMesh &m = c_.mesh;
    const size_t joints = c_.jointCount();
    std::vector<glm::dvec3> lo(joints, glm::dvec3(INFINITY)), hi(joints, glm::dvec3(-INFINITY));
    for (size_t v = 0; v < m.vertexCount(); ++v)
      for (int i = 0; i < 4; ++i)
        if (m.weights[v][i] > 0) {
          const size_t j = m.joints[v][i];
          lo[j] = glm::min(lo[j], glm::dvec3(m.positions[v]));
          hi[j] = glm::max(hi[j], glm::dvec3(m.positions[v]));
        }
    shells_.assign(joints, {});
    jointError_.assign(joints, 0.0);
    for (size_t j = 0; j < joints; ++j) {
      if (lo[j].x > hi[j].x)
        continue; // moves no vertex
      for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 p(corner & 1 ? hi[j].x : lo[j].x, corner & 2 ? hi[j].y : lo[j].y,
                           corner & 4 ? hi[j].z : lo[j].z);
        shells_[j].push_back(glm::dvec3(c_.inverseBind[j] * glm::dvec4(p, 1.0)));
      }
    }
  }

  // Every channel's key times (seconds since the clip's start), a cut's time twice. Times on a
  // uniform grid (within kUniformSlack of a step) are moved onto it, so the table is one step.
  void buildTimes() {
    std::map<double, uint32_t> count;
    for (const Channel *ch : channelOf_) {
      if (!ch)
        continue;
      std::map<double, uint32_t> own;
      for (double t : ch->times)
        ++own[t - clip_.start];
      for (const auto &[t, n] : own)
        count[t] = std::max(count[t], n);
    }
    if (count.empty())
      count[0.0] = 1;
    for (const auto &[t, n] : count)
      for (uint32_t i = 0; i < n; ++i) {
        times_.push_back(std::max(t, 0.0));
        fromLeft_.push_back(i + 1 < n); // the first of a cut ends the span before it
      }
    keys_ = uint32_t(times_.size());
    // Values are sampled at the keys' own times and stored at times a float holds: a key time
    // rounded down would sample a STEP key's predecessor.
    sampleAt_ = times_;
    for (double &t : times_)
      t = double(float(t));
    const size_t n = times_.size();
    if (n < 3 || times_.front() != 0.0)
      return;
    const double step = times_.back() / double(n - 1);
    for (size_t i = 0; i < n; ++i)
      if (!(std::abs(times_[i] - double(i) * step) <= kUniformSlack * step))
        return;
    const float stepF = float(step);
    for (size_t i = 0; i < n; ++i)
      times_[i] = double(float(double(i) * double(stepF)));
  }

  std::vector<Trs> exactPose(double t, bool fromLeft) const {
    std::vector<Trs> pose(nodes_);
    for (size_t k = 0; k < nodes_; ++k) {
      const Node &node = c_.nodes[size_t(rig_.sourceNode[k])];
      pose[k] = {node.rotation, node.translation, node.scale};
      for (int p = 0; p < 3; ++p) {
        const Channel *ch = channelOf_[k * 3 + size_t(p)];
        if (!ch)
          continue;
        double v[4];
        sampleChannel(*ch, clip_.start + t, v, fromLeft);
        if (p == 0)
          pose[k].r = glm::dquat(v[3], v[0], v[1], v[2]);
        else if (p == 1)
          pose[k].t = {v[0], v[1], v[2]};
        else
          pose[k].s = {v[0], v[1], v[2]};
      }
    }
    return pose;
  }

  std::vector<glm::dmat4> globals(const std::vector<Trs> &pose) const {
    std::vector<glm::dmat4> g(nodes_);
    for (size_t k = 0; k < nodes_; ++k) {
      const Node &node = c_.nodes[size_t(rig_.sourceNode[k])];
      const glm::dmat4 local =
          node.hasMatrix ? node.matrix : trsMatrix(pose[k].r, pose[k].t, pose[k].s);
      const int parent = rig_.skeleton.parents[k];
      g[k] = parent >= 0 ? g[size_t(parent)] * local : local;
    }
    return g;
  }

  // The largest error over joints' boxes between two sets of globals.
  double poseError(const std::vector<glm::dmat4> &a, const std::vector<glm::dmat4> &b) const {
    double worst = 0;
    for (size_t j = 0; j < shells_.size(); ++j)
      worst = std::max(worst, jointError(j, a, b));
    return worst;
  }
  double jointError(size_t j, const std::vector<glm::dmat4> &a,
                    const std::vector<glm::dmat4> &b) const {
    const size_t k = rig_.skeleton.jointNodes[j];
    double worst = 0;
    for (const glm::dvec3 &p : shells_[j])
      worst = std::max(worst, glm::length(glm::dvec3(a[k] * glm::dvec4(p, 1.0)) -
                                          glm::dvec3(b[k] * glm::dvec4(p, 1.0))));
    return worst;
  }

  // Poses `a` and `b` interpolated `s` of the way as the decoder does: slerp, lerp, STEP held.
  std::vector<Trs> mixPoses(const std::vector<Trs> &a, const std::vector<Trs> &b, double s) const {
    std::vector<Trs> mix(nodes_);
    for (size_t k = 0; k < nodes_; ++k) {
      const Channel *r = channelOf_[k * 3];
      const bool holdR = r && r->interpolation == Interpolation::Step;
      mix[k].r =
          holdR ? a[k].r
                : glm::dquat(runtime::slerpShorter(glm::quat(a[k].r), glm::quat(b[k].r), float(s)));
      const Channel *tc = channelOf_[k * 3 + 1], *sc = channelOf_[k * 3 + 2];
      mix[k].t =
          tc && tc->interpolation == Interpolation::Step ? a[k].t : glm::mix(a[k].t, b[k].t, s);
      mix[k].s =
          sc && sc->interpolation == Interpolation::Step ? a[k].s : glm::mix(a[k].s, b[k].s, s);
    }
    return mix;
  }

  // Bisects (t0, t1) while linear interpolation of the exact values at its ends departs from
  // the exact pose at its quarter points by more than a quarter of the tolerance.
  struct Samples {
    std::vector<double> times, at;
    std::vector<uint8_t> left;
  };
  void split(double t0, double t1, int depth, Samples &out) const {
    if (depth >= kMaxSplits)
      return;
    const auto a = exactPose(t0, false), b = exactPose(t1, true);
    double worst = 0;
    for (double s : {0.25, 0.5, 0.75})
      worst = std::max(worst, poseError(globals(mixPoses(a, b, s)),
                                        globals(exactPose(t0 + (t1 - t0) * s, false))));
    if (worst <= 0.25 * tolerance_)
      return;
    const double mid = 0.5 * (t0 + t1);
    split(t0, mid, depth + 1, out);
    out.times.push_back(double(float(mid)));
    out.at.push_back(double(float(mid)));
    out.left.push_back(0);
    split(mid, t1, depth + 1, out);
  }

  void classify(size_t t) {
    pack::Track &track = tracks_[t];
    const Channel *ch = channelOf_[t];
    const Node &node = c_.nodes[size_t(rig_.sourceNode[t / 3])];
    if (!ch || node.hasMatrix)
      return; // Default
    track.step = ch->interpolation == Interpolation::Step;
    const auto &v = exact_[t];
    std::array<double, 3> lo = v[0], hi = v[0];
    for (const auto &x : v)
      for (int c = 0; c < 3; ++c)
        lo[size_t(c)] = std::min(lo[size_t(c)], x[size_t(c)]),
        hi[size_t(c)] = std::max(hi[size_t(c)], x[size_t(c)]);
    std::array<double, 3> rest;
    if (t % 3 == 0) {
      glm::dquat q = node.rotation;
      if (q.w < 0)
        q = -q;
      rest = {q.x, q.y, q.z};
    } else {
      const glm::dvec3 r = t % 3 == 1 ? node.translation : node.scale;
      rest = {r.x, r.y, r.z};
    }
    bool atRest = true, constant = true;
    for (int c = 0; c < 3; ++c) {
      const double scale = std::max(1.0, std::abs(rest[size_t(c)]));
      atRest &= std::abs(lo[size_t(c)] - rest[size_t(c)]) <= 1e-7 * scale &&
                std::abs(hi[size_t(c)] - rest[size_t(c)]) <= 1e-7 * scale;
      constant &= hi[size_t(c)] - lo[size_t(c)] <= 1e-9 * scale;
    }
    if (atRest)
      return;
    if (constant) {
      track.kind = pack::TrackKind::Constant;
      for (int c = 0; c < 3; ++c)
        track.min[size_t(c)] = float(lo[size_t(c)]);
      deq_[t].assign(v.size(), track.min);
      return;
    }
    track.kind = pack::TrackKind::Animated;
    if (t % 3 == 0)
      dropFarthestFromZero(t, lo, hi);
    for (int c = 0; c < 3; ++c)
      floatRange(lo[size_t(c)], hi[size_t(c)], track.min[size_t(c)], track.extent[size_t(c)]);
    setBits(t, pack::kMaxTrackBits);
    track.bits = 0; // lossless until allotBits sets it
  }

  // An animated rotation's dropped component: the one whose smallest magnitude over the clip is
  // largest (w, as the reader assumes, where none is farther), and its stored values and range.
  void dropFarthestFromZero(size_t t, std::array<double, 3> &lo, std::array<double, 3> &hi) {
    const auto &qs = rotations_[t / 3];
    double smallest[4] = {INFINITY, INFINITY, INFINITY, INFINITY};
    for (const glm::dquat &q : qs) {
      const double xyzw[4] = {q.x, q.y, q.z, q.w};
      for (size_t i = 0; i < 4; ++i)
        smallest[i] = std::min(smallest[i], std::abs(xyzw[i]));
    }
    uint32_t dropped = 0;
    for (uint32_t d = 1; d < 4; ++d)
      if (smallest[droppedIndex(d)] > smallest[droppedIndex(dropped)])
        dropped = d;
    tracks_[t].dropped = uint8_t(dropped);
    auto &v = exact_[t];
    for (size_t s = 0; s < v.size(); ++s)
      v[s] = storedRotation(qs[s], dropped);
    lo = hi = v[0];
    for (const auto &x : v)
      for (size_t c = 0; c < 3; ++c)
        lo[c] = std::min(lo[c], x[c]), hi[c] = std::max(hi[c], x[c]);
  }

  void setBits(size_t t, uint32_t bits) {
    deq_[t] = valuesAt(t, bits);
    tracks_[t].bits = uint8_t(bits);
  }

  using Values = std::vector<std::array<float, 3>>; // per sample, as decoded

  // Track t's values at `bits` (its range as it stands).
  Values valuesAt(size_t t, uint32_t bits) const {
    const pack::Track &track = tracks_[t];
    Values out(times_.size());
    for (size_t s = 0; s < times_.size(); ++s)
      for (size_t c = 0; c < 3; ++c)
        out[s][c] =
            dequantize(track.min[c], track.extent[c],
                       quantize(exact_[t][s][c], track.min[c], track.extent[c], bits), bits);
    return out;
  }

  // The local matrix of track node k at sample s as the tracks now stand, or with track
  // `other` taking the values `instead`.
  glm::dmat4 decodedLocal(size_t k, size_t s, size_t other = SIZE_MAX,
                          const Values *instead = nullptr) const {
    const Node &node = c_.nodes[size_t(rig_.sourceNode[k])];
    if (node.hasMatrix)
      return node.matrix;
    const auto value = [&](size_t t) -> const std::array<float, 3> & {
      return t == other ? (*instead)[s] : deq_[t][s];
    };
    glm::dquat r = node.rotation;
    glm::dvec3 tr = node.translation, sc = node.scale;
    if (tracks_[k * 3].kind != pack::TrackKind::Default)
      r = rotationOf(value(k * 3), tracks_[k * 3].dropped);
    if (tracks_[k * 3 + 1].kind != pack::TrackKind::Default) {
      const auto &v = value(k * 3 + 1);
      tr = {v[0], v[1], v[2]};
    }
    if (tracks_[k * 3 + 2].kind != pack::TrackKind::Default) {
      const auto &v = value(k * 3 + 2);
      sc = {v[0], v[1], v[2]};
    }
    return trsMatrix(r, tr, sc);
  }

  // Threads for a loop of `work` node or corner transforms: a loop of fewer than kSharedWork
  // runs on one thread, where waking helpers costs more than they share.
  int threadsFor(size_t work) const { return work >= kSharedWork ? threads_ : 1; }

  void updateLocal(size_t k) {
    for (size_t s = 0; s < times_.size(); ++s)
      local_[s][k] = decodedLocal(k, s);
  }

  static constexpr size_t kEveryNode = SIZE_MAX;
  // Globals of node `from` and every node below it (kEveryNode: of every root's), then the
  // errors of their joints.
  void updateGlobals(size_t from) {
    std::vector<uint8_t> below(nodes_, from == kEveryNode);
    const auto &parents = rig_.skeleton.parents;
    if (from == kEveryNode)
      from = 0;
    for (size_t k = from; k < nodes_; ++k)
      below[k] = below[k] || k == from || (parents[k] >= 0 && below[size_t(parents[k])]);
    std::vector<size_t> joints; // whose errors change
    for (size_t j = 0; j < shells_.size(); ++j)
      if (below[rig_.skeleton.jointNodes[j]])
        joints.push_back(j);
    std::vector<double> errors(times_.size() * joints.size()); // per sample, per joint
    size_t changed = joints.size();
    for (size_t k = from; k < nodes_; ++k)
      changed += below[k];
    parallelFor(times_.size(), threadsFor(times_.size() * changed), [&](size_t s) {
      for (size_t k = from; k < nodes_; ++k)
        if (below[k])
          global_[s][k] =
              parents[k] >= 0 ? global_[s][size_t(parents[k])] * local_[s][k] : local_[s][k];
      for (size_t i = 0; i < joints.size(); ++i)
        errors[s * joints.size() + i] = jointError(joints[i], global_[s], exactGlobals_[s]);
    });
    for (size_t i = 0; i < joints.size(); ++i) {
      double worst = 0;
      for (size_t s = 0; s < times_.size(); ++s)
        worst = std::max(worst, errors[s * joints.size() + i]);
      jointError_[joints[i]] = worst;
    }
  }

  // Applies track node k's current values; true when every joint then errs within `limit`.
  bool commitWithin(size_t k, double limit) {
    updateLocal(k);
    updateGlobals(k);
    return std::all_of(jointError_.begin(), jointError_.end(),
                       [&](double e) { return e <= limit; });
  }

  // What every candidate raise of one joint's chain shares, per sample: the exact pose's
  // corners of the joint's box, and per chain node the decoded locals below it times them.
  using Corners = std::vector<std::array<glm::dvec4, 8>>; // per sample
  struct ChainSamples {
    std::vector<std::array<glm::dvec3, 8>> exactCorners;
    std::vector<Corners> belowCorners; // per chain node
  };

  // How far joint j's box errs over `limit`, summed over the samples, with chain track t (of
  // chain node chain[at]) at `bits` and the rest as they are. A sum, not the largest: where two
  // tracks each make the worst error at a sample of their own, raising either lowers the sum.
  // Every term is >= 0: once `enough` says the sum so far is too large, it is returned unfinished.
  template <class Enough>
  double excessWith(size_t j, const std::vector<size_t> &chain, size_t at, size_t t, uint32_t bits,
                    double limit, const ChainSamples &shared, const Enough &enough) const {
    const Values values = valuesAt(t, bits);
    double excess = 0;
    const size_t k = chain[at];
    const int parent = rig_.skeleton.parents[k];
    const auto &corners = shells_[j];
    const Corners &below = shared.belowCorners[at];
    for (size_t s = 0; s < times_.size(); ++s) {
      glm::dmat4 g = decodedLocal(k, s, t, &values);
      if (parent >= 0)
        g = global_[s][size_t(parent)] * g;
      double worst = 0;
      for (size_t i = 0; i < corners.size(); ++i)
        worst =
            std::max(worst, glm::length(glm::dvec3(g * below[s][i]) - shared.exactCorners[s][i]));
      excess += std::max(0.0, worst - limit);
      if (enough(excess))
        return excess;
    }
    return excess;
  }

  // More bits on the animated track of joint j's chain that lowers j's excess over `limit` most
  // per bit added, looking up to kRaiseLookahead bits ahead: one more bit can leave a sample's
  // value where it was (on both grids), where two or three do not. Where none lowers it, the
  // coarsest below kFloorBits; false where there is none. The chain is walked from j up, each
  // node's locals below it built on the last; the first best in root-down order is taken.
  bool raiseFor(size_t j, double limit) {
    std::vector<size_t> chain; // track nodes from the root down to j's
    for (int k = int(rig_.skeleton.jointNodes[j]); k >= 0; k = rig_.skeleton.parents[size_t(k)])
      chain.push_back(size_t(k));
    std::reverse(chain.begin(), chain.end());
    const size_t n = times_.size();
    ChainSamples shared;
    shared.exactCorners.resize(n);
    shared.belowCorners.resize(chain.size());
    for (size_t s = 0; s < n; ++s)
      for (size_t i = 0; i < shells_[j].size(); ++i)
        shared.exactCorners[s][i] =
            glm::dvec3(exactGlobals_[s][chain.back()] * glm::dvec4(shells_[j][i], 1.0));
    struct Candidate {
      size_t at, t;
      uint32_t bits;
      double excess;
    };
    const auto raisable = [&](size_t t) {
      return tracks_[t].kind == pack::TrackKind::Animated && tracks_[t].bits < pack::kMaxTrackBits;
    };
    size_t first = SIZE_MAX; // the first raisable track root-down: where the excess now is taken
    for (size_t at = 0; at < chain.size() && first == SIZE_MAX; ++at)
      for (size_t p = 0; p < 3 && first == SIZE_MAX; ++p)
        if (raisable(chain[at] * 3 + p))
          first = chain[at] * 3 + p;
    std::vector<Candidate> tried; // bottom-up
    size_t fewest = SIZE_MAX;
    std::vector<glm::dmat4> below(n, glm::dmat4(1.0)); // the product of the locals under `at`
    for (size_t at = chain.size(); at-- > 0;) {
      if (at + 1 < chain.size())
        for (size_t s = 0; s < n; ++s)
          below[s] = local_[s][chain[at + 1]] * below[s];
      bool any = false;
      for (size_t p = 3; p-- > 0;) {
        const size_t t = chain[at] * 3 + p;
        if (!raisable(t))
          continue;
        any = true;
        if (fewest == SIZE_MAX || tracks_[t].bits <= tracks_[fewest].bits)
          fewest = t; // the first in root-down order among the coarsest
        for (uint32_t more = kRaiseLookahead + 1; more-- > (t == first ? 0u : 1u);) {
          const uint32_t bits = tracks_[t].bits + more; // reversed below with the rest
          if (bits <= pack::kMaxTrackBits)
            tried.push_back({at, t, bits, 0.0});
        }
      }
      if (!any)
        continue;
      Corners &corners = shared.belowCorners[at];
      corners.resize(n);
      for (size_t s = 0; s < n; ++s)
        for (size_t i = 0; i < shells_[j].size(); ++i)
          corners[s][i] = below[s] * glm::dvec4(shells_[j][i], 1.0);
    }
    std::reverse(tried.begin(), tried.end()); // root-down, each track's bits ascending
    // The excess as it stands, measured on the first track's path.
    double now = -1;
    for (Candidate &c : tried)
      if (c.bits == tracks_[c.t].bits)
        now = c.excess =
            excessWith(j, chain, c.at, c.t, c.bits, limit, shared, [](double) { return false; });
    // Each raise measured on its own, and left unfinished (as infinite) once its gain cannot
    // reach the best gain found so far: the best, and the first of equals, are the same in any
    // order of measuring.
    std::atomic<double> found{0.0}; // the best gain so far, at least 0
    parallelFor(tried.size(), threadsFor(tried.size() * n * shells_[j].size()), [&](size_t i) {
      Candidate &c = tried[i];
      const double more = double(c.bits - tracks_[c.t].bits);
      if (more == 0)
        return;
      bool unfinished = false;
      const double e = excessWith(j, chain, c.at, c.t, c.bits, limit, shared, [&](double partial) {
        return unfinished = (now - partial) / more < found.load(std::memory_order_relaxed);
      });
      c.excess = unfinished ? INFINITY : e;
      const double gain = (now - c.excess) / more;
      for (double was = found.load(); gain > was && !found.compare_exchange_weak(was, gain);) {
      }
    });
    size_t best = SIZE_MAX;
    uint32_t bestBits = 0;
    double bestGain = 0;
    for (const Candidate &c : tried) {
      if (c.bits == tracks_[c.t].bits)
        continue;
      const double gain = (now - c.excess) / double(c.bits - tracks_[c.t].bits);
      if (gain > bestGain)
        best = c.t, bestBits = c.bits, bestGain = gain;
    }
    if (best == SIZE_MAX) { // errors that cancel: one more bit on the coarsest track
      if (fewest == SIZE_MAX || tracks_[fewest].bits >= kFloorBits)
        return false;
      best = fewest, bestBits = tracks_[fewest].bits + 1u;
    }
    setBits(best, bestBits);
    updateLocal(best / 3);
    updateGlobals(best / 3);
    return true;
  }

  const Character &c_;
  const TrackRig &rig_;
  const AnimationClip &clip_;
  double tolerance_;
  int threads_;
  size_t nodes_;
  std::vector<const Channel *> channelOf_;      // per track, its channel or null
  std::vector<std::vector<glm::dvec3>> shells_; // per joint
  std::vector<double> times_;       // per sample, since the clip's start, as stored (floats)
  std::vector<double> sampleAt_;    // per sample, the time its values are sampled at
  std::vector<uint8_t> fromLeft_;   // per sample: the first of a cut
  std::vector<double> allSampleAt_; // sampleAt_ before dropSamples
  uint32_t keys_ = 0;
  std::vector<std::vector<std::array<double, 3>>> exact_; // per track, per sample
  std::vector<std::vector<glm::dmat4>> exactGlobals_;     // per sample, per track node
  std::vector<std::vector<glm::dquat>> rotations_;        // per track node, per sample: exact
  std::vector<pack::Track> tracks_;
  std::vector<std::vector<std::array<float, 3>>> deq_;  // per track, per sample: as decoded
  std::vector<std::vector<glm::dmat4>> local_, global_; // per sample, per track node: decoded
  std::vector<double> jointError_; // per joint: the largest over the samples of its box's error
};

} // namespace

TrackRig trackRig(const Character &c) {
  std::vector<uint8_t> keep(c.nodes.size(), 0);
  for (int j : c.jointNodes)
    for (int n = j; n >= 0 && !keep[size_t(n)]; n = c.nodes[size_t(n)].parent)
      keep[size_t(n)] = 1;
  TrackRig rig;
  std::vector<int> index(c.nodes.size(), -1);
  for (int n : c.nodeOrder) {
    if (!keep[size_t(n)])
      continue;
    const Node &node = c.nodes[size_t(n)];
    index[size_t(n)] = int(rig.sourceNode.size());
    rig.sourceNode.push_back(n);
    rig.skeleton.parents.push_back(node.parent >= 0 ? index[size_t(node.parent)] : -1);
    std::array<float, 12> rest{};
    if (node.hasMatrix) {
      for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 4; ++col)
          rest[size_t(row * 4 + col)] = float(node.matrix[col][row]);
    } else {
      rest = {float(node.rotation.x),
              float(node.rotation.y),
              float(node.rotation.z),
              float(node.rotation.w),
              float(node.translation.x),
              float(node.translation.y),
              float(node.translation.z),
              float(node.scale.x),
              float(node.scale.y),
              float(node.scale.z),
              0.0f,
              0.0f};
    }
    rig.skeleton.rest.push_back(rest);
    rig.skeleton.restIsMatrix.push_back(node.hasMatrix ? 1 : 0);
  }
  for (int j : c.jointNodes)
    rig.skeleton.jointNodes.push_back(uint32_t(index[size_t(j)]));
  return rig;
}

double TrackClipFigures::maxAnyTimeMm() const {
  return std::max({maxAtSamplesMm, maxAtMidsMm, maxAtRandomMm});
}

VertexErrors trackErrors(const Character &c, const TrackRig &rig, const pack::TrackClip &tracks,
                         const AnimationClip &clip, const std::vector<double> &seconds, int threads,
                         const PlayedMorphs &played, const SkinErrorBound *cull) {
  const SkinnedMesh &m = c.mesh;
  const bool withMean = !cull;
  std::vector<float> inverseBind(c.jointCount() * 16);
  for (size_t j = 0; j < c.jointCount(); ++j)
    for (int k = 0; k < 16; ++k)
      inverseBind[j * 16 + size_t(k)] = float(c.inverseBind[j][k / 4][k % 4]);
  // Squared distances until the end: the root of the largest is the largest root, to the bit.
  // The largest found so far at any time of the set: where it rises first does not change it.
  std::atomic<double> found{0.0};
  const uint32_t vertices = uint32_t(m.vertexCount());
  std::vector<double> largest(seconds.size(), 0.0), sum(seconds.size(), 0.0);
  const bool morphed = played.morphs || !m.morphs.empty();
  parallelFor(seconds.size(), threads, [&](size_t i) {
    const double t = clip.start + seconds[i];
    const auto palette = runtime::skinningPalette(
        rig.skeleton, runtime::decodeLocalPose(rig.skeleton, tracks, float(seconds[i])),
        inverseBind);
    const auto exact = jointMatrices(c, &clip, t);
    const auto weights = morphWeights(c, &clip, t);
    const runtime::ClipTime at =
        played.morphs ? runtime::clipTimeAt(*played.clip, float(seconds[i])) : runtime::ClipTime{};
    SkinErrorBound::Terms terms;
    if (cull) {
      std::vector<runtime::JointRows> rows;
      for (const glm::mat4 &j : palette)
        rows.push_back(runtime::toRows(j));
      terms = cull->terms(rows, exact);
    }
    double most = withMean ? 0.0 : found.load(), total = 0; // locals: slots share cache lines
    for (uint32_t v = 0; v < vertices; ++v) {
      if (cull && cull->blocks() && v % SkinErrorBound::kBlock == 0 &&
          cull->block(v / SkinErrorBound::kBlock, terms) <= most) {
        v += SkinErrorBound::kBlock - 1;
        continue;
      }
      const glm::dvec3 exactBind =
          m.morphs.empty() ? glm::dvec3(m.positions[v]) : morphedPosition(m, weights, v);
      const glm::dvec3 bindD =
          played.morphs ? glm::dvec3(runtime::morphVertex(*played.morphs, at, uint32_t(v),
                                                          {m.positions[v], m.normals[v]})
                                         .position)
                        : exactBind;
      if (cull && (morphed ? cull->morphedVertex(v, terms, glm::dvec3(glm::vec3(bindD)), exactBind)
                           : cull->vertex(v, terms)) <= most)
        continue; // cannot raise the largest (a NaN bound can)
      const glm::vec4 bind(glm::vec3(bindD), 1.0f);
      glm::vec3 skinned(0.0f);
      for (int k = 0; k < 4; ++k)
        if (m.weights[v][k] > 0)
          skinned += m.weights[v][k] * glm::vec3(palette[m.joints[v][k]] * bind);
      const glm::dvec3 off = glm::dvec3(skinned) - skinPosition(m, exact, weights, v);
      const double squared = glm::dot(off, off);
      most = std::max(most, squared);
      if (withMean)
        total += std::sqrt(squared);
    }
    largest[i] = most;
    sum[i] = total;
    for (double was = found.load(); most > was && !found.compare_exchange_weak(was, most);) {
    }
  });
  VertexErrors out;
  for (size_t i = 0; i < seconds.size(); ++i) {
    out.max = std::max(out.max, largest[i]);
    out.mean += sum[i];
  }
  out.max = std::sqrt(out.max);
  const double count = double(seconds.size()) * double(std::max<size_t>(vertices, 1));
  out.mean = !withMean || seconds.empty() ? 0.0 : out.mean / count;
  return out;
}

namespace {

// The times the mean is reported over: seeded by the clip's index, so a rebake measures the same.
std::vector<double> randomTimes(const AnimationClip &clip, size_t clipIndex) {
  const double duration = clip.end - clip.start;
  return duration > 0 ? seededTimes(clipIndex, duration) : std::vector<double>{};
}

// One compression of a clip with samples dropped within `dropShare` (0: none); `uniformBefore`
// tells whether its time table was one step before any were dropped. Its figures hold the
// largest errors; the mean is left to the clip that is kept (reportMean).
CompressedClip compressWith(const Character &c, const TrackRig &rig, const AnimationClip &clip,
                            size_t clipIndex, const TrackCompressionOptions &options,
                            const PlayedMorphs &played, const SkinErrorBound &bound,
                            double dropShare, bool &uniformBefore) {
  const double budget = options.errorBudgetMm / options.mmPerUnit; // model units
  ClipCompressor compressor(c, rig, clip, budget, options.threads);
  compressor.refineCurves();
  // The TRAK decoder's bound, checked before the samples are evaluated.
  if (compressor.times().size() > limits::kTrackSamples)
    throw Error("clip '" + clip.name + "': " + std::to_string(compressor.times().size()) +
                " samples (its keys and those CUBICSPLINE spans need) are more than joint tracks "
                "hold (" +
                std::to_string(limits::kTrackSamples) +
                "); bake it as a texture (--store texture) or split the clip");
  std::vector<float> before;
  for (double t : compressor.times())
    before.push_back(float(t));
  uniformBefore = pack::uniformTimes(before);
  compressor.dropSamples(dropShare);
  compressor.sampleTracks();
  compressor.makeConstant();
  compressor.halveConstants();
  const auto &times = compressor.times();
  std::vector<double> mids;
  for (size_t i = 0; i + 1 < times.size(); ++i)
    if (times[i + 1] > times[i])
      mids.push_back(0.5 * (times[i] + times[i + 1]));
  const std::vector<double> random = randomTimes(clip, clipIndex);

  CompressedClip out;
  TrackClipFigures &f = out.figures;
  double share = kSampleShare;
  for (int round = 0; round < kTighteningRounds; ++round) {
    compressor.allotBits(share);
    out.clip = compressor.build();
    // Each set skins only the vertices that may raise its largest.
    f.maxAtSamplesMm = trackErrors(c, rig, out.clip, clip, compressor.sampleTimes(),
                                   options.threads, played, &bound)
                           .max *
                       options.mmPerUnit;
    f.maxAtMidsMm = trackErrors(c, rig, out.clip, clip, mids, options.threads, played, &bound).max *
                    options.mmPerUnit;
    f.maxAtRandomMm =
        trackErrors(c, rig, out.clip, clip, random, options.threads, played, &bound).max *
        options.mmPerUnit;
    f.met = f.maxAnyTimeMm() <= options.errorBudgetMm;
    if (f.met)
      break;
    share *= 0.9 * options.errorBudgetMm / f.maxAnyTimeMm();
  }
  f.clip = clip.name;
  f.keys = compressor.keys();
  f.samples = uint32_t(out.clip.times.size());
  f.sampledKeys = uint32_t(compressor.sampleTimes().size());
  double bits = 0;
  for (const pack::Track &t : out.clip.tracks) {
    f.defaultTracks += t.kind == pack::TrackKind::Default;
    f.constantTracks += t.kind == pack::TrackKind::Constant;
    if (t.kind == pack::TrackKind::Animated) {
      ++f.animatedTracks;
      bits += t.bits;
    }
  }
  f.meanBits = f.animatedTracks ? bits / f.animatedTracks : 0.0;
  f.bytes = pack::clipBytes(out.clip);
  return out;
}

} // namespace

CompressedClip compressClip(const Character &c, const TrackRig &rig, const AnimationClip &clip,
                            size_t clipIndex, const TrackCompressionOptions &options,
                            const PlayedMorphs &played) {
  options.validate();
  const pack::SkinTexture skin = buildSkinTexture(c.mesh, limits::kTextureSide);
  const SkinErrorBound bound(c.mesh, skin, c.jointCount());
  // The mean at the random times skins every vertex: measured once, on the clip kept.
  const auto reportMean = [&](CompressedClip cc) {
    cc.figures.meanAtRandomMm =
        trackErrors(c, rig, cc.clip, clip, randomTimes(clip, clipIndex), options.threads, played)
            .mean *
        options.mmPerUnit;
    return cc;
  };
  bool uniform = false;
  CompressedClip dropped =
      compressWith(c, rig, clip, clipIndex, options, played, bound, kDropShare, uniform);
  const TrackClipFigures &f = dropped.figures;
  if (f.samples == f.sampledKeys)
    return reportMean(std::move(dropped)); // nothing was dropped
  // Every sample kept, where that can take fewer bytes: the drops missed the budget, or a
  // one-step time table became a list that costs more than the samples dropped save (at the
  // same bits).
  const double timeTable = pack::uniformTimes(dropped.clip.times) ? 0.0 : 4.0 * f.samples;
  const double saved = double(f.sampledKeys - f.samples) * f.animatedTracks * 3 * f.meanBits / 8;
  if (f.met && !(uniform && saved < timeTable))
    return reportMean(std::move(dropped));
  CompressedClip kept = compressWith(c, rig, clip, clipIndex, options, played, bound, 0.0, uniform);
  const bool keptWins = kept.figures.met != f.met ? kept.figures.met : kept.figures.bytes < f.bytes;
  return reportMean(keptWins ? std::move(kept) : std::move(dropped));
}

} // namespace crowd
