#include "crowd/bake/cloth_loop.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "crowd/formats/error.h"

namespace crowd {

namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

LoopChoice chooseLoop(uint32_t frameCount, uint32_t vertexCount, const ClothFrames &frames,
                      const std::vector<uint32_t> &indices, const ClothLoopOptions &options) {
  options.validate();
  for (uint32_t i : indices)
    if (i >= vertexCount)
      throw Error("cloth loop: a garment triangle names vertex " + std::to_string(i) +
                  " of a cache of " + std::to_string(vertexCount));
  LoopChoice out;
  auto t0 = std::chrono::steady_clock::now();
  const LoopSearch search = searchLoops(frameCount, vertexCount, frames, options.search);
  out.pass1Seconds = secondsSince(t0);
  out.meanMotion = search.meanMotion;
  out.meanVelocityChange = search.meanVelocityChange;
  out.distances = search.distances;
  out.minCycles = search.minCycles;
  out.maxCycles = search.maxCycles;
  out.frames = frameCount;
  std::vector<double> seams;
  for (double d : search.distances)
    if (!std::isnan(d))
      seams.push_back(d);
  std::nth_element(seams.begin(), seams.begin() + seams.size() / 2, seams.end());
  const double median = seams[seams.size() / 2];

  t0 = std::chrono::steady_clock::now();
  std::vector<glm::vec3> first, last;
  for (uint32_t rank = 0; rank < search.candidates.size(); ++rank) {
    ClothLoopCandidate c;
    c.seam = search.candidates[rank];
    c.pass1Rank = rank;
    frames(c.seam.start, 0, vertexCount, first);
    frames(c.seam.start + c.seam.length, 0, vertexCount, last);
    c.edgeDistances = edgeDistances(first, last, indices, options.edges);
    for (double d : c.edgeDistances)
      c.edgeDistance += d;
    out.candidates.push_back(std::move(c));
  }
  out.pass2Seconds = secondsSince(t0);
  std::stable_sort(out.candidates.begin(), out.candidates.end(),
                   [](const auto &a, const auto &b) { return a.edgeDistance < b.edgeDistance; });

  const LoopCandidate &best = out.candidates.front().seam;
  const auto ratio = [](double a, double b) { return b > 0 ? a / b : (a > 0 ? INFINITY : 0.0); };
  out.positionRatio = ratio(best.positionJump, out.meanMotion);
  out.velocityRatio = ratio(best.velocityJump, out.meanVelocityChange);
  out.bestToMedian = ratio(best.distance, median);
  const double worst = std::max(out.positionRatio, out.velocityRatio);
  out.acceptable = worst <= options.exactRatio ||
                   (worst <= options.maxJumpRatio && out.bestToMedian <= options.maxToMedian);
  char line[400];
  if (out.acceptable) {
    std::snprintf(line, sizeof line,
                  "loop of %u cycles from frame %u: seam jumps %.2f x the mean per-frame motion "
                  "and %.2f x the mean velocity change, %.2f x the median seam: a hard cut",
                  best.cycles, best.start, out.positionRatio, out.velocityRatio, out.bestToMedian);
  } else {
    out.blendFrames = uint32_t(std::ceil(std::min(worst / options.exactRatio, 1e6)));
    std::snprintf(line, sizeof line,
                  "no acceptable loop: the best seam (%u cycles from frame %u) jumps %.2f x the "
                  "mean per-frame motion and %.2f x the mean velocity change (limit %.2f), and "
                  "is %.2f x the median seam (limit %.2f; about 1 for a cache that never "
                  "repeats); a cross-fade over %u frames would be needed",
                  best.cycles, best.start, out.positionRatio, out.velocityRatio,
                  options.maxJumpRatio, out.bestToMedian, options.maxToMedian, out.blendFrames);
  }
  out.verdict = line;
  return out;
}

} // namespace crowd
