#include "anim_accuracy.h"

#include <algorithm>
#include <cmath>

#include "crowd/bake/evaluate.h"
#include "crowd/bake/morph_frames.h"
#include "crowd/bake/parallel.h"
#include "crowd/runtime/texture_skinning.h"

namespace crowd {
namespace {

// Every precision's error at a time of one of the pack's clips, all sharing the morphed bind
// positions: the largest and the sum over the vertices, per precision.
class PrecisionMeter {
public:
  PrecisionMeter(const Character &c, const pack::AnimationPack &pk,
                 const std::vector<pack::AnimationTexture> &textures)
      : c_(c), pk_(pk), textures_(textures) {}
  size_t precisions() const { return textures_.size(); }
  void measure(size_t ci, uint32_t frame, float alpha, const std::vector<glm::dvec3> &exact,
               double *max, double *sum) const {
    const runtime::ClipTime at{&pk_.clips[ci], frame, alpha};
    std::vector<std::vector<runtime::JointRows>> sampled;
    for (const auto &t : textures_)
      sampled.push_back(runtime::sampleJoints(t, pk_.clips[ci], frame, alpha));
    // Locals, written once: the callers' slots of neighbouring times share cache lines.
    std::vector<double> most(max, max + textures_.size()), total(sum, sum + textures_.size());
    for (uint32_t v = 0; v < uint32_t(c_.mesh.vertexCount()); ++v) {
      const glm::vec3 bind = morphedBind(c_.mesh, pk_.morphs, at, v); // the same for every p
      for (size_t p = 0; p < textures_.size(); ++p) {
        double e =
            glm::length(glm::dvec3(runtime::skinVertex(sampled[p], pk_.skin, v, bind)) - exact[v]);
        most[p] = std::max(most[p], e);
        total[p] += e;
      }
    }
    std::copy(most.begin(), most.end(), max);
    std::copy(total.begin(), total.end(), sum);
  }

private:
  const Character &c_;
  const pack::AnimationPack &pk_;
  const std::vector<pack::AnimationTexture> &textures_;
};

// Per precision p, the error at each frame (at, f * np + p) and at its mid-frame.
struct FrameErrors {
  std::vector<double> frameMax, frameSum, midMax, midSum;
};
FrameErrors measureFrames(const Character &c, const std::vector<ClipFrames> &clips,
                          const ExactFrames &frames, const PrecisionMeter &meter, int threads,
                          FrameBounds &bounds) {
  const size_t total = frames.count(), np = meter.precisions();
  FrameErrors e{std::vector<double>(total * np), std::vector<double>(total * np),
                std::vector<double>(total * np), std::vector<double>(total * np)};
  bounds.low.assign(total, glm::dvec3(INFINITY));
  bounds.high.assign(total, glm::dvec3(-INFINITY));
  parallelFor(total, threads, [&](size_t f) {
    const size_t ci = frames.list[f].first;
    const uint32_t i = frames.list[f].second;
    const auto exact = framePositions(c, frames, f);
    glm::dvec3 low(INFINITY), high(-INFINITY);
    for (const auto &q : exact)
      low = glm::min(low, q), high = glm::max(high, q);
    bounds.low[f] = low, bounds.high[f] = high;
    meter.measure(ci, i, 0.0f, exact, &e.frameMax[f * np], &e.frameSum[f * np]);
    const auto &cf = clips[ci];
    if (i + 1 < cf.count)
      meter.measure(ci, i, 0.5f, posedPositions(c, cf.clip, cf.start + (i + 0.5) * cf.step),
                    &e.midMax[f * np], &e.midSum[f * np]);
  });
  return e;
}

// Random times: uniform over each clip's duration, from a fixed seed per clip (the budget's).
struct RandomErrors {
  std::vector<std::pair<size_t, double>> times; // (clip, seconds into the clip)
  std::vector<double> max, sum;                 // at (r * np + p)
};
RandomErrors measureRandomTimes(const Character &c, const std::vector<ClipFrames> &clips,
                                const pack::AnimationPack &pk, const PrecisionMeter &meter,
                                int threads) {
  const size_t np = meter.precisions();
  RandomErrors e;
  for (size_t ci = 0; ci < clips.size(); ++ci)
    if (clips[ci].count > 1)
      for (double t : seededTimes(ci, clips[ci].clip->end - clips[ci].clip->start))
        e.times.push_back({ci, t});
  e.max.resize(e.times.size() * np);
  e.sum.resize(e.times.size() * np);
  parallelFor(e.times.size(), threads, [&](size_t r) {
    const auto [ci, t] = e.times[r];
    const auto exact = posedPositions(c, clips[ci].clip, clips[ci].start + t);
    uint32_t frame;
    float alpha;
    runtime::frameAt(pk.clips[ci], float(t), frame, alpha);
    meter.measure(ci, frame, alpha, exact, &e.max[r * np], &e.sum[r * np]);
  });
  return e;
}

// Precision p's figures per clip, from the errors at frames, mid-frames and random times.
std::vector<ClipAccuracy> clipAccuracy(const pack::AnimationPack &pk, size_t p, size_t np,
                                       double vertices, const FrameErrors &fe,
                                       const RandomErrors &re) {
  std::vector<ClipAccuracy> out;
  size_t f = 0, r = 0;
  for (size_t ci = 0; ci < pk.clips.size(); ++ci) {
    const pack::Clip &clip = pk.clips[ci];
    ClipAccuracy a{clip.name, clip.frameCount};
    for (uint32_t i = 0; i < clip.frameCount; ++i, ++f) {
      a.maxAtFrames = std::max(a.maxAtFrames, fe.frameMax[f * np + p]);
      a.meanAtFrames += fe.frameSum[f * np + p] / (vertices * clip.frameCount);
      a.maxAtMidframes = std::max(a.maxAtMidframes, fe.midMax[f * np + p]);
      if (clip.frameCount > 1)
        a.meanAtMidframes += fe.midSum[f * np + p] / (vertices * (clip.frameCount - 1));
    }
    for (; r < re.times.size() && re.times[r].first == ci; ++r) {
      a.maxAtRandom = std::max(a.maxAtRandom, re.max[r * np + p]);
      a.meanAtRandom += re.sum[r * np + p] / (vertices * kRandomTimesPerClip);
    }
    out.push_back(a);
  }
  return out;
}

} // namespace

FrameBounds measurePrecisions(const Character &c, const std::vector<ClipFrames> &clips,
                              const ExactFrames &frames, const std::vector<uint32_t> &matrixJoints,
                              const AnimBakeOptions &options, AnimBakeResult &result,
                              Reporter &reporter) {
  auto &pk = result.pack;
  const auto &all = precisions();
  std::vector<pack::AnimationTexture> textures;
  for (const auto &p : all)
    textures.push_back(
        buildAnimationTexture(frames.joints, c.jointCount(), p, options.maxWidth, matrixJoints));
  reporter.step("accuracy: " + std::to_string(all.size()) + " precisions at " +
                std::to_string(frames.count()) + " frames, their mid-frames and random times");
  const PrecisionMeter meter(c, pk, textures);
  FrameBounds bounds;
  const FrameErrors fe = measureFrames(c, clips, frames, meter, options.threads, bounds);
  const RandomErrors re = measureRandomTimes(c, clips, pk, meter, options.threads);
  const Precision &chosen = precisionByName(result.budget.precision);
  for (size_t p = 0; p < all.size(); ++p) {
    PrecisionAccuracy pa{all[p], textures[p].texels.size(), {}};
    pa.clips = clipAccuracy(pk, p, all.size(), double(c.mesh.vertexCount()), fe, re);
    if (all[p].name == chosen.name) {
      result.baked = result.accuracy.size();
      pk.animation = std::move(textures[p]);
    }
    result.accuracy.push_back(std::move(pa));
  }
  return bounds;
}

} // namespace crowd
