#include "crowd/bake/anim_budget.h"

#include <algorithm>
#include <cmath>

#include "crowd/bake/evaluate.h"
#include "crowd/bake/morph_frames.h"
#include "crowd/bake/parallel.h"
#include "crowd/formats/limits.h"
#include "crowd/runtime/texture_skinning.h"
#include "skin_error_bound.h"

namespace crowd {
namespace {

std::vector<double> ratesFor(const BudgetSearch &s, double source) {
  if (s.sourceRateOnly)
    return {source};
  std::vector<double> rates = s.rates;
  if (rates.empty()) {
    rates.assign(kRateLadder.begin(), kRateLadder.end());
    rates.push_back(source);
  }
  std::sort(rates.begin(), rates.end());
  rates.erase(std::unique(rates.begin(), rates.end(),
                          [](double a, double b) { return std::abs(a - b) < 1e-4 * b; }),
              rates.end());
  return rates;
}

// Largest vertex error of each texture, against exact evaluation, at the clip's frame times
// (`joints`: their exact matrices), its mid-frames and the seeded random times. Squared
// distances until the end: the root of the largest is the largest root, to the bit. Only the
// vertices whose SkinErrorBound exceeds the largest error found so far are skinned: the same
// figures, to the bit, in a fraction of the time (the whole anim bake of many_clips, 23k triangles
// and 24 clips: 0.33 of the time; CesiumMan 0.64, Fox 0.79, the humanoid 0.86, against e46ceff
// in tests/bench/anim_speed.sh).
std::vector<double> maxErrors(const Character &c, const ClipFrames &f,
                              const std::vector<std::vector<glm::dmat4>> &joints,
                              const std::vector<std::vector<double>> &morphs,
                              const std::vector<pack::AnimationTexture> &textures,
                              const pack::SkinTexture &skin, const SkinErrorBound &bound,
                              const std::optional<pack::Morphs> &morphFrames,
                              const std::vector<double> &randomTimes,
                              const std::vector<std::vector<glm::dmat4>> &randomJoints,
                              const std::vector<std::vector<double>> &randomMorphs, int threads) {
  pack::Clip clip;
  clip.fps = float(f.fps);
  clip.frameCount = f.count;
  const SkinnedMesh &m = c.mesh;
  const size_t frames = f.count, mids = f.count - 1, np = textures.size();
  const size_t n = frames + mids + randomTimes.size(), vertices = m.vertexCount();
  const bool morphed = !m.morphs.empty();
  // The random times first, then the mid-frames, then the frames (where the textures hold the
  // exact matrices: the least error): each group starts from the largest error those before it
  // found, so that fewer of its vertices are skinned.
  std::vector<double> perTime(n * np, 0.0), before(np, 0.0);
  auto measure = [&](size_t k) {
    uint32_t frame;
    float alpha;
    std::vector<glm::dmat4> midJoints;
    std::vector<double> midMorphs;
    const std::vector<glm::dmat4> *exactJoints = &midJoints;
    const std::vector<double> *exactMorphs = &midMorphs;
    if (k < frames) {
      frame = uint32_t(k), alpha = 0.0f;
      exactJoints = &joints[k], exactMorphs = &morphs[k];
    } else if (k < frames + mids) {
      frame = uint32_t(k - frames), alpha = 0.5f;
      const double t = f.start + (double(frame) + 0.5) * f.step;
      midJoints = jointMatrices(c, f.clip, t), midMorphs = morphWeights(c, f.clip, t);
    } else {
      const size_t r = k - frames - mids;
      runtime::frameAt(clip, float(randomTimes[r]), frame, alpha);
      exactJoints = &randomJoints[r], exactMorphs = &randomMorphs[r];
    }
    const runtime::ClipTime at{&clip, frame, alpha};
    std::vector<std::vector<runtime::JointRows>> sampled;
    std::vector<SkinErrorBound::Terms> terms; // per precision
    for (const auto &texture : textures) {
      sampled.push_back(runtime::sampleJoints(texture, clip, frame, alpha));
      terms.push_back(bound.terms(sampled.back(), *exactJoints));
    }
    double *largest = &perTime[k * np];
    std::copy(before.begin(), before.end(), largest);
    auto below = [&](auto boundOf) { // whether every precision's bound is within its largest
      for (size_t p = 0; p < np; ++p)
        if (!(boundOf(terms[p]) <= largest[p])) // a NaN bound skips nothing
          return false;
      return true;
    };
    for (uint32_t v = 0; v < vertices; ++v) {
      if (bound.blocks() && v % SkinErrorBound::kBlock == 0 &&
          below([&](const auto &t) { return bound.block(v / SkinErrorBound::kBlock, t); })) {
        v += SkinErrorBound::kBlock - 1;
        continue;
      }
      const glm::vec3 bind = morphedBind(m, morphFrames, at, v); // the same for every p
      const glm::dvec3 exactBind = morphed ? morphedPosition(m, *exactMorphs, v) : glm::dvec3(0);
      bool skinned = false;
      glm::dvec3 exact;
      for (size_t p = 0; p < np; ++p) {
        const double most =
            morphed ? bound.morphedVertex(v, terms[p], bind, exactBind) : bound.vertex(v, terms[p]);
        if (most <= largest[p])
          continue; // cannot raise the largest (a NaN bound can)
        if (!skinned) {
          exact = skinPosition(m, *exactJoints, *exactMorphs, v);
          skinned = true;
        }
        const glm::dvec3 off = glm::dvec3(runtime::skinVertex(sampled[p], skin, v, bind)) - exact;
        largest[p] = std::max(largest[p], glm::dot(off, off));
      }
    }
  };
  for (const auto &[first, last] : {std::pair(frames + mids, n), std::pair(frames, frames + mids),
                                    std::pair(size_t(0), frames)}) {
    parallelFor(last - first, threads, [&](size_t i) { measure(first + i); });
    for (size_t k = first; k < last; ++k)
      for (size_t p = 0; p < np; ++p)
        before[p] = std::max(before[p], perTime[k * np + p]);
  }
  for (double &e : before)
    e = std::sqrt(e);
  return before;
}

// The smallest precision tried: its bytes per frame, the pack's floor.
uint64_t fewestFrameBytes(const Character &c, const BudgetSearch &s) {
  uint64_t bytes = UINT64_MAX;
  for (const Precision *p : s.tried)
    bytes = std::min(bytes, p->frameBytes(c.jointCount(), s.matrixJoints.size()));
  return bytes;
}

// A clip's fewest frames: at the lowest rate it tries.
uint64_t fewestFrames(const AnimationClip &clip, const BudgetSearch &s) {
  return planFrames(clip, ratesFor(s, sourceRate(clip)).front()).count;
}

// Every option of one clip, trying rates lowest first and dropping a precision once it meets the
// budget, below `cap` bytes at the smallest precision; best[p] gets the option chosen for
// precision p.
ClipBudget searchClip(const Character &c, const AnimationClip &clip, size_t clipIndex,
                      const BudgetSearch &s, uint64_t cap, const pack::SkinTexture &skin,
                      const SkinErrorBound &bound, std::vector<size_t> &best) {
  ClipBudget cb;
  cb.clip = clip.name;
  cb.sourceFps = sourceRate(clip);
  const double duration = clip.end - clip.start;
  const size_t np = s.tried.size();
  // A frame's joints, and its morph slots (target, weight) where the mesh has targets.
  const uint64_t morphSlotBytes = c.mesh.morphs.empty() ? 0 : pack::kMorphSlots * 2 * sizeof(float);
  const auto bytes = [&](uint32_t frames, const Precision &p) {
    return frames * (p.frameBytes(c.jointCount(), s.matrixJoints.size()) + morphSlotBytes);
  };
  const auto rates = ratesFor(s, cb.sourceFps);
  if (!(duration > 0)) { // one frame: every rate stores the same pose
    for (size_t p = 0; p < np; ++p) {
      best[p] = cb.tried.size();
      cb.tried.push_back({rates.front(), s.tried[p]->name, 1, bytes(1, *s.tried[p]), 0, true});
    }
    return cb;
  }
  const auto randomTimes = seededTimes(clipIndex, duration); // the same at every rate
  std::vector<std::vector<glm::dmat4>> randomJoints(randomTimes.size());
  std::vector<std::vector<double>> randomMorphs(randomTimes.size());
  parallelFor(randomTimes.size(), s.threads, [&](size_t k) {
    randomJoints[k] = jointMatrices(c, &clip, clip.start + randomTimes[k]);
    randomMorphs[k] = morphWeights(c, &clip, clip.start + randomTimes[k]);
  });
  std::vector<size_t> open(np);
  for (size_t p = 0; p < np; ++p)
    open[p] = p;
  for (double rate : rates) {
    if (open.empty())
      break;
    if (!cb.tried.empty() && duration * rate >= double(limits::kClipFrames))
      break; // higher rates would not fit a clip
    const ClipFrames f = planFrames(clip, rate);
    if (!cb.tried.empty() && f.count * fewestFrameBytes(c, s) >= cap) {
      cb.capped = true; // no higher rate can take fewer bytes than the cap either
      break;
    }
    std::vector<std::vector<glm::dmat4>> joints(f.count);
    std::vector<std::vector<double>> morphs(f.count);
    parallelFor(f.count, s.threads, [&](size_t i) {
      joints[i] = jointMatrices(c, &clip, f.start + double(i) * f.step);
      morphs[i] = morphWeights(c, &clip, f.start + double(i) * f.step);
    });
    const auto morphFrames = buildMorphs(c.mesh, morphs);
    std::vector<pack::AnimationTexture> textures;
    for (size_t p : open)
      textures.push_back(
          buildAnimationTexture(joints, c.jointCount(), *s.tried[p], s.maxWidth, s.matrixJoints));
    const auto errors = maxErrors(c, f, joints, morphs, textures, skin, bound, morphFrames,
                                  randomTimes, randomJoints, randomMorphs, s.threads);
    std::vector<size_t> still;
    for (size_t k = 0; k < open.size(); ++k) {
      const size_t p = open[k];
      const double mm = errors[k] * s.mmPerUnit;
      const bool meets = mm <= s.budgetMm;
      if (meets || best[p] == SIZE_MAX ||
          mm < cb.tried[best[p]].maxErrorMm * 0.99) // else the lower rate stays the best
        best[p] = cb.tried.size();
      cb.tried.push_back(
          {f.fps, s.tried[p]->name, f.count, bytes(f.count, *s.tried[p]), mm, meets});
      if (!meets)
        still.push_back(p);
    }
    open = std::move(still);
  }
  return cb;
}

} // namespace

std::vector<uint32_t> matrixJointsByBudget(const Character &c,
                                           const std::vector<const AnimationClip *> &clips,
                                           double budgetMm, double mmPerUnit, int threads) {
  std::vector<std::vector<glm::dmat4>> frames;
  for (const AnimationClip *clip : clips) {
    const ClipFrames f = planFrames(*clip, std::min(sourceRate(*clip), kRateLadder.back()));
    const size_t first = frames.size();
    frames.resize(first + f.count);
    parallelFor(f.count, threads, [&](size_t i) {
      frames[first + i] = jointMatrices(c, clip, f.start + double(i) * f.step);
    });
  }
  if (clips.empty())
    frames.push_back(jointMatrices(c, nullptr, 0.0));
  return matrixJointsFor(c.mesh, c.jointCount(), frames, 0.5 * budgetMm / mmPerUnit);
}

uint64_t fewestTextureBytes(const Character &c, const std::vector<const AnimationClip *> &clips,
                            const BudgetSearch &s) {
  uint64_t frames = clips.empty() ? 1 : 0; // the rest pose
  for (const AnimationClip *clip : clips)
    frames += fewestFrames(*clip, s);
  return frames * fewestFrameBytes(c, s);
}

BudgetChoice chooseByBudget(const Character &c, const std::vector<const AnimationClip *> &clips,
                            const BudgetSearch &s) {
  const size_t np = s.tried.size();
  const pack::SkinTexture skin = buildSkinTexture(c.mesh, s.maxWidth);
  const SkinErrorBound bound(c.mesh, skin, c.jointCount());
  BudgetChoice out;
  out.searched = true;
  std::vector<std::vector<size_t>> best(clips.size(), std::vector<size_t>(np, SIZE_MAX));
  const uint64_t fewest = fewestTextureBytes(c, clips, s);
  for (size_t ci = 0; ci < clips.size(); ++ci) {
    if (s.step)
      s.step("error budget: clip " + std::to_string(ci + 1) + " of " +
             std::to_string(clips.size()) + " (" + clips[ci]->name + ")");
    // This clip's share of the cap: what the others leave at their fewest.
    const uint64_t others = fewest - fewestFrames(*clips[ci], s) * fewestFrameBytes(c, s);
    const uint64_t cap = s.fewerBytesThan > others ? s.fewerBytesThan - others : 0;
    out.clips.push_back(searchClip(c, *clips[ci], ci, s, cap, skin, bound, best[ci]));
  }
  // The precision: fewest bytes among those meeting the budget everywhere, else the smallest
  // worst error (within 1%, the fewer bytes).
  size_t chosen = 0;
  std::vector<uint64_t> bytes(np, 0);
  std::vector<double> worst(np, 0);
  std::vector<bool> met(np, true);
  for (size_t p = 0; p < np; ++p)
    for (size_t ci = 0; ci < clips.size(); ++ci) {
      const BudgetOption &o = out.clips[ci].tried[best[ci][p]];
      bytes[p] += o.bytes;
      worst[p] = std::max(worst[p], o.maxErrorMm);
      met[p] = met[p] && o.meets;
    }
  for (size_t p = 1; p < np; ++p) {
    const bool better = met[chosen]
                            ? met[p] && bytes[p] < bytes[chosen]
                            : met[p] || worst[p] < worst[chosen] * 0.99 ||
                                  (worst[p] <= worst[chosen] * 1.01 && bytes[p] < bytes[chosen]);
    if (better)
      chosen = p;
  }
  out.precision = s.tried[chosen]->name;
  out.matrixJoints = s.matrixJoints;
  out.met = met[chosen];
  out.bytes = bytes[chosen];
  for (size_t ci = 0; ci < clips.size(); ++ci)
    out.clips[ci].fps = out.clips[ci].tried[best[ci][chosen]].fps;
  return out;
}

} // namespace crowd
