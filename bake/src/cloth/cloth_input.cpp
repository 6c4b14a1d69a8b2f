#include "crowd/bake/cloth_input.h"

#include <algorithm>
#include <cmath>

#include "crowd/bake/evaluate.h"
#include "crowd/formats/error.h"

namespace crowd {

namespace {

// The skeleton's top joint: the first whose node's parent is no joint.
int topJointNode(const Character &c) {
  for (int node : c.jointNodes)
    if (std::find(c.jointNodes.begin(), c.jointNodes.end(), c.nodes[size_t(node)].parent) ==
        c.jointNodes.end())
      return node;
  return -1;
}

} // namespace

const AnimationClip &findClip(const Character &body, const std::string &name) {
  for (const auto &c : body.clips)
    if (c.name == name)
      return c;
  throw unknownName("clip", name, body.clipNames());
}

double cacheFrameTime(const AnimationClip &clip, uint32_t frame, double fps) {
  const double duration = clip.end - clip.start, t = frame / fps;
  return clip.start + (duration > 0 ? std::fmod(t, duration) : 0.0);
}

std::vector<uint32_t> garmentVertices(const Character &outfit, const std::string &garment) {
  std::vector<std::string> names;
  for (const auto &part : outfit.mesh.parts) {
    names.push_back(part.name);
    if (part.name != garment)
      continue;
    std::vector<uint32_t> ids(outfit.mesh.indices.begin() + part.firstIndex,
                              outfit.mesh.indices.begin() + part.firstIndex + part.indexCount);
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    return ids;
  }
  throw unknownName("garment", garment, names);
}

double cacheFps(const PointCacheReader &cache, const ClothCacheOptions &options) {
  options.validate();
  if (options.fps > 0.0)
    return options.fps;
  if (cache.info().fps > 0.0)
    return cache.info().fps;
  throw Error(cache.path() + ": a PC2 file stores no frame rate; give --fps");
}

void checkGarment(PointCacheReader &cache, const Character &outfit,
                  const std::vector<uint32_t> &garment, const AnimationClip &clip,
                  const ClothCacheOptions &options) {
  options.validate();
  if (cache.info().vertexCount != garment.size())
    throw Error(cache.path() + ": " + std::to_string(cache.info().vertexCount) +
                " vertices, but the garment has " + std::to_string(garment.size()) +
                " (a cache of another garment, or of a different mesh?)");
  std::vector<glm::vec3> first;
  cache.readFrame(0, first);
  const std::vector<glm::dvec3> posed = posedPositions(outfit, &clip, clip.start);
  std::vector<double> distance(garment.size());
  for (size_t v = 0; v < garment.size(); ++v)
    distance[v] = glm::length(glm::dvec3(first[v]) - posed[garment[v]]);
  std::nth_element(distance.begin(), distance.begin() + distance.size() / 2, distance.end());
  const double median = distance[distance.size() / 2];
  const double limit = options.orderTolerance * restDiagonal(outfit);
  if (median > limit)
    throw Error(cache.path() + ": frame 0 is not the garment at the start of clip '" + clip.name +
                "': the median vertex is " + std::to_string(median) + " away (limit " +
                std::to_string(limit) + "); the cache's vertex order differs from the glTF's, " +
                "or it starts elsewhere in the clip");
}

FrameRateFit fitFrameRate(PointCacheReader &cache, const Character &outfit,
                          const std::vector<uint32_t> &garment, const AnimationClip &clip,
                          double fps) {
  FrameRateFit fit;
  const uint32_t frameCount = cache.info().frameCount;
  if (garment.empty() || frameCount < 2 || !(clip.end > clip.start))
    return fit;
  // The body-bound vertices, by distance then index (the same on every machine).
  std::vector<glm::vec3> positions;
  cache.readFrame(0, positions);
  const std::vector<glm::dvec3> rest = posedPositions(outfit, &clip, clip.start);
  std::vector<std::pair<double, uint32_t>> bound(garment.size());
  for (uint32_t v = 0; v < garment.size(); ++v)
    bound[v] = {glm::length(glm::dvec3(positions[v]) - rest[garment[v]]), v};
  const size_t count = std::max<size_t>(1, bound.size() / 10);
  std::partial_sort(bound.begin(), bound.begin() + ptrdiff_t(count), bound.end());
  bound.resize(count);
  const uint32_t samples = std::min<uint32_t>(frameCount, 48);
  std::vector<uint32_t> frames(samples);
  std::vector<std::vector<glm::dvec3>> at(samples);
  for (uint32_t k = 0; k < samples; ++k) {
    frames[k] = uint32_t(uint64_t(k) * (frameCount - 1) / std::max<uint32_t>(1, samples - 1));
    cache.readFrame(frames[k], positions);
    for (const auto &b : bound)
      at[k].push_back(glm::dvec3(positions[b.second]));
  }
  const auto residual = [&](double rate) {
    double sum = 0.0;
    for (uint32_t k = 0; k < samples; ++k) {
      const auto posed = posedPositions(outfit, &clip, cacheFrameTime(clip, frames[k], rate));
      for (size_t i = 0; i < count; ++i)
        sum += glm::length(at[k][i] - posed[garment[bound[i].second]]);
    }
    return sum / double(size_t(samples) * count);
  };
  fit.residual = residual(fps);
  for (double rate : {24.0, 25.0, 30.0, 48.0, 50.0, 60.0}) {
    if (std::abs(rate - fps) < 1e-3 * rate)
      continue;
    const double r = residual(rate);
    if (fit.bestRate == 0.0 || r < fit.bestResidual)
      fit.bestRate = rate, fit.bestResidual = r;
  }
  fit.mismatch = fit.bestRate > 0.0 && fit.bestResidual < 0.5 * fit.residual &&
                 fit.residual > 0.002 * restDiagonal(outfit);
  return fit;
}

glm::dmat4 toRootFrame(const Character &body, const AnimationClip &clip, uint32_t frame,
                       double fps) {
  const int top = topJointNode(body);
  if (top < 0)
    return glm::dmat4(1.0);
  return glm::inverse(nodeGlobals(body, &clip, cacheFrameTime(clip, frame, fps))[size_t(top)]);
}

ClothFrames rootFrames(PointCacheReader &cache, const Character &body, const AnimationClip &clip,
                       double fps) {
  return [&cache, &body, &clip, fps](uint32_t frame, uint32_t first, uint32_t count,
                                     std::vector<glm::vec3> &out) {
    cache.read(frame, first, count, out);
    if (body.jointNodes.empty())
      return;
    const glm::dmat4 toRoot = toRootFrame(body, clip, frame, fps);
    for (auto &p : out)
      p = glm::vec3(toRoot * glm::dvec4(glm::dvec3(p), 1.0));
  };
}

} // namespace crowd
