#include "crowd/bake/loop_search.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "crowd/bake/parallel.h"
#include "crowd/formats/error.h"

namespace crowd {

namespace {

constexpr uint32_t kBlock = 512; // vertices per block: frameCount x 6 KiB held at a time
constexpr size_t kStride = 3 * kBlock;

// One lag's seam terms over one block of vertices, for every start s: the position term
// |d(s)|^2 and the velocity term |d(s + 1) - d(s)|^2 of the differences d(s) = p(s + len) -
// p(s). Each d is formed once; 8 independent lanes let the compiler vectorise the sums
// without reassociating them.
void lagTerms(const float *block, uint32_t frames, uint32_t len, double *pos, double *vel) {
  std::vector<float> prev(kStride), next(kStride);
  const auto diff = [&](uint32_t s, float *d) {
    const float *a = block + size_t(s + len) * kStride, *b = block + size_t(s) * kStride;
    float p[8] = {};
    for (size_t j = 0; j < kStride; j += 8)
      for (size_t l = 0; l < 8; ++l) {
        d[j + l] = a[j + l] - b[j + l];
        p[l] += d[j + l] * d[j + l];
      }
    for (float x : p)
      pos[s] += x;
  };
  diff(0, prev.data());
  for (uint32_t s = 0; s + len + 1 < frames; ++s) {
    diff(s + 1, next.data());
    float v[8] = {};
    for (size_t j = 0; j < kStride; j += 8)
      for (size_t l = 0; l < 8; ++l) {
        const float dv = next[j + l] - prev[j + l];
        v[l] += dv * dv;
      }
    for (float x : v)
      vel[s] += x;
    std::swap(prev, next);
  }
}

double meanLength(const std::vector<glm::vec3> &a, const std::vector<glm::vec3> &b,
                  const std::vector<glm::vec3> &c, const std::vector<glm::vec3> &d) {
  double sum = 0.0; // mean |(a - b) - (c - d)|
  for (size_t v = 0; v < a.size(); ++v)
    sum += glm::length(glm::dvec3(a[v] - b[v]) - glm::dvec3(c[v] - d[v]));
  return sum / double(a.size());
}

} // namespace

LoopSearch searchLoops(uint32_t frameCount, uint32_t vertexCount, const ClothFrames &frames,
                       const LoopSearchOptions &options) {
  options.validate();
  const double cycle = options.cycleFrames;
  const uint32_t n = frameCount, w = options.window;
  const auto length = [&](uint32_t c) { return uint32_t(std::lround(c * cycle)); };
  if (vertexCount == 0)
    throw Error("cloth loop: the cache has no vertices");
  if (n < 2.0 * cycle + 2 * w + 2)
    throw Error("cloth loop: the cache's " + std::to_string(n) + " frames hold " +
                std::to_string(n / cycle).substr(0, 4) + " body-clip cycles of " +
                std::to_string(cycle).substr(0, 6) +
                " frames; the search needs at least 2 cycles (simulate longer)");
  LoopSearch out;
  out.minCycles = options.minCycles;
  // A loop (s, L) needs frames s - w .. s + L + w + 1 (the last for the velocity).
  for (uint32_t c = options.minCycles;
       length(c) + 2 * w + 2 <= n && (options.maxCycles == 0 || c <= options.maxCycles); ++c)
    out.maxCycles = c;
  if (out.maxCycles < out.minCycles)
    throw Error("cloth loop: no loop of " + std::to_string(options.minCycles) +
                " cycles or more fits in " + std::to_string(n) + " frames");
  const uint32_t lengths = out.maxCycles - out.minCycles + 1;

  // Raw seam terms per (length, start), accumulated block by block; task `lengths` sums the
  // yardsticks (per-frame motion and velocity change).
  std::vector<double> pos(size_t(lengths) * n, 0.0), vel(size_t(lengths) * n, 0.0);
  double motion = 0.0, change = 0.0;
  std::vector<float> block(size_t(n) * kStride);
  std::vector<glm::vec3> read;
  for (uint32_t first = 0; first < vertexCount; first += kBlock) {
    const uint32_t count = std::min(kBlock, vertexCount - first);
    std::fill(block.begin(), block.end(), 0.0f); // padding lanes stay 0 in every frame
    for (uint32_t f = 0; f < n; ++f) {
      frames(f, first, count, read);
      std::copy_n(&read[0].x, 3 * size_t(count), block.data() + size_t(f) * kStride);
    }
    const auto at = [&](uint32_t f) { return block.data() + size_t(f) * kStride; };
    parallelFor(lengths + 1, options.threads, [&](size_t task) {
      if (task == lengths) {
        for (uint32_t f = 0; f + 1 < n; ++f)
          for (uint32_t v = 0; v < count; ++v) {
            const glm::vec3 *p0 = reinterpret_cast<const glm::vec3 *>(at(f)) + v;
            const glm::vec3 step = p0[kBlock] - p0[0]; // kBlock vec3 = one frame later
            motion += glm::length(glm::dvec3(step));
            if (f + 2 < n)
              change += glm::length(glm::dvec3(p0[2 * kBlock] - p0[kBlock] - step));
          }
        return;
      }
      lagTerms(block.data(), n, length(out.minCycles + uint32_t(task)), pos.data() + task * n,
               vel.data() + task * n);
    });
  }
  out.meanMotion = motion / (double(n - 1) * vertexCount);
  out.meanVelocityChange = change / (double(n - 2) * vertexCount);

  // Filter along the diagonal with binomial weights; rank; keep one loop per length within
  // half a cycle of start.
  std::vector<double> weights(2 * w + 1, 0.0);
  weights[0] = 1.0;
  for (uint32_t i = 1; i <= 2 * w; ++i) // row 2w of Pascal's triangle, then normalised
    for (uint32_t j = i; j > 0; --j)
      weights[j] += weights[j - 1];
  double total = 0.0;
  for (double x : weights)
    total += x;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  out.distances.assign(size_t(lengths) * n, nan);
  struct Ranked {
    double distance;
    uint32_t task, start;
  };
  std::vector<Ranked> ranked;
  for (uint32_t task = 0; task < lengths; ++task) {
    const uint32_t len = length(out.minCycles + task);
    for (uint32_t s = w; s + len + w + 1 < n; ++s) {
      double sum = 0.0;
      for (uint32_t m = 0; m <= 2 * w; ++m) {
        const size_t i = size_t(task) * n + s + m - w;
        sum += weights[m] * (pos[i] + options.velocityWeight * vel[i]);
      }
      const double d = sum / (total * vertexCount);
      out.distances[size_t(task) * n + s] = d;
      ranked.push_back({d, task, s});
    }
  }
  std::sort(ranked.begin(), ranked.end(), [](const Ranked &a, const Ranked &b) {
    return a.distance != b.distance ? a.distance < b.distance
                                    : (a.task != b.task ? a.task < b.task : a.start < b.start);
  });
  std::vector<glm::vec3> s0, s1, e0, e1;
  for (const Ranked &r : ranked) {
    if (out.candidates.size() == options.candidates)
      break;
    const uint32_t cycles = out.minCycles + r.task;
    const bool near = std::any_of(out.candidates.begin(), out.candidates.end(), [&](auto &c) {
      return c.cycles == cycles && std::abs(double(c.start) - r.start) < cycle / 2;
    });
    if (near)
      continue;
    LoopCandidate c;
    c.start = r.start;
    c.cycles = cycles;
    c.length = length(cycles);
    c.phaseError = std::abs(c.length - cycles * cycle);
    c.distance = r.distance;
    frames(c.start, 0, vertexCount, s0);
    frames(c.start + 1, 0, vertexCount, s1);
    frames(c.start + c.length, 0, vertexCount, e0);
    frames(c.start + c.length + 1, 0, vertexCount, e1);
    const std::vector<glm::vec3> zero(vertexCount, glm::vec3(0));
    c.positionJump = meanLength(e0, s0, zero, zero);
    c.velocityJump = meanLength(e1, e0, s1, s0);
    out.candidates.push_back(c);
  }
  return out;
}

} // namespace crowd
