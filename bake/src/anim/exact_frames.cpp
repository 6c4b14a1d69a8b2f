#include "exact_frames.h"

#include "crowd/bake/evaluate.h"
#include "crowd/bake/parallel.h"

namespace crowd {

ExactFrames sampleFrames(const Character &c, const std::vector<ClipFrames> &clips, int threads) {
  ExactFrames frames;
  for (size_t ci = 0; ci < clips.size(); ++ci)
    for (uint32_t i = 0; i < clips[ci].count; ++i)
      frames.list.push_back({ci, i});
  frames.joints.resize(frames.count());
  frames.morphWeights.resize(frames.count());
  parallelFor(frames.count(), threads, [&](size_t f) {
    const auto &cf = clips[frames.list[f].first];
    const uint32_t i = frames.list[f].second;
    frames.joints[f] = jointMatrices(c, cf.clip, cf.start + i * cf.step);
    frames.morphWeights[f] = morphWeights(c, cf.clip, cf.start + i * cf.step);
  });
  return frames;
}

std::vector<glm::dvec3> framePositions(const Character &c, const ExactFrames &frames, size_t f) {
  return skinPositions(c, frames.joints[f], frames.morphWeights[f]);
}

} // namespace crowd
