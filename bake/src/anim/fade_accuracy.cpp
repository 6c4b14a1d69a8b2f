#include "crowd/bake/fade_accuracy.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_access.hpp>

#include "crowd/bake/evaluate.h"
#include "crowd/bake/parallel.h"
#include "crowd/runtime/texture_skinning.h"
#include "crowd/runtime/track_palettes.h"

namespace crowd {

double sourceSeconds(const AnimationClip &source, const pack::Clip &baked, double seconds) {
  const double duration = source.end - source.start;
  if (baked.loop && duration > 0 && (seconds < 0 || seconds > duration)) // frameAt's rule
    seconds -= duration * std::floor(seconds / duration);
  return source.start + std::clamp(seconds, 0.0, std::max(duration, 0.0));
}

std::vector<glm::dmat4> blendedJoints(const std::vector<glm::dmat4> &from,
                                      const std::vector<glm::dmat4> &to, float weight) {
  std::vector<glm::dmat4> out(from.size());
  for (size_t j = 0; j < from.size(); ++j)
    out[j] = glm::dmat4(runtime::toMat4(runtime::blendJoints(
        runtime::toRows(glm::mat4(from[j])), runtime::toRows(glm::mat4(to[j])), weight)));
  return out;
}

FadeAccuracy measureFades(const Character &c, const std::vector<const AnimationClip *> &sources,
                          const pack::AnimationPack &pack, int threads) {
  std::vector<std::pair<uint32_t, uint32_t>> all, pairs;
  for (uint32_t a = 0; a < sources.size(); ++a)
    for (uint32_t b = 0; b < sources.size(); ++b)
      if (a != b)
        all.push_back({a, b});
  for (size_t k = 0; k < std::min<size_t>(all.size(), kFadePairs); ++k) // spread over the list
    pairs.push_back(all[k * all.size() / std::min<size_t>(all.size(), kFadePairs)]);
  FadeAccuracy out;
  out.pairs = uint32_t(pairs.size());
  const size_t samples = pairs.size() * kFadeSamplesPerPair;
  const uint32_t vertices = uint32_t(c.mesh.vertexCount());
  std::vector<double> max(samples), sum(samples);
  parallelFor(samples, threads, [&](size_t s) {
    const auto [a, b] = pairs[s / kFadeSamplesPerPair];
    uint64_t state = 0x9e3779b97f4a7c15ull * (s + 1);
    auto uniform = [&] { // PCG's LCG step, as the clips' seeded times
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      return double(state >> 11) * 0x1.0p-53;
    };
    const double ta = uniform() * (sources[a]->end - sources[a]->start),
                 tb = uniform() * (sources[b]->end - sources[b]->start);
    const auto weight = float(uniform());
    const double sa = sourceSeconds(*sources[a], pack.clips[a], ta),
                 sb = sourceSeconds(*sources[b], pack.clips[b], tb);
    // Morph weights blend linearly: the exact fade of the two clips' weights.
    auto morphs = morphWeights(c, sources[a], sa);
    const auto morphsTo = morphWeights(c, sources[b], sb);
    for (size_t k = 0; k < morphs.size(); ++k)
      morphs[k] += (morphsTo[k] - morphs[k]) * double(weight);
    // The texture fades blended joint matrices, joint tracks blend local poses.
    const auto exact = skinPositions(
        c,
        pack.hasTexture() ? blendedJoints(jointMatrices(c, sources[a], sa),
                                          jointMatrices(c, sources[b], sb), weight)
                          : jointMatrices(c, blendLocals(nodeLocals(c, sources[a], sa),
                                                         nodeLocals(c, sources[b], sb), weight)),
        morphs);
    const auto from = runtime::clipTimeAt(pack.clips[a], float(ta)),
               to = runtime::clipTimeAt(pack.clips[b], float(tb));
    std::vector<runtime::JointRows> palette;
    if (!pack.hasTexture())
      for (const glm::mat4 &m :
           runtime::decodePalette(pack, {float(b), float(tb), float(a), float(ta), weight}))
        palette.push_back({glm::row(m, 0), glm::row(m, 1), glm::row(m, 2)});
    double most = 0, total = 0; // locals: neighbouring slots share cache lines
    for (uint32_t v = 0; v < vertices; ++v) {
      glm::vec3 bind = c.mesh.positions[v];
      if (pack.morphs)
        bind = runtime::morphVertexFaded(*pack.morphs, from, to, weight, v, {bind, glm::vec3(0)})
                   .position;
      const glm::vec3 drawn = pack.hasTexture()
                                  ? runtime::skinVertexFaded(pack.animation, pack.skin, from, to,
                                                             weight, v, bind, glm::vec3(0.0f))
                                        .position
                                  : runtime::skinVertex(palette, pack.skin, v, bind);
      const double e = glm::length(glm::dvec3(drawn) - exact[v]);
      most = std::max(most, e);
      total += e;
    }
    max[s] = most, sum[s] = total;
  });
  for (size_t s = 0; s < samples; ++s) {
    out.maxError = std::max(out.maxError, max[s]);
    out.meanError += sum[s] / (double(vertices) * double(samples));
  }
  return out;
}

} // namespace crowd
