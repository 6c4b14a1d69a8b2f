// Pass 1 of the cloth-loop search on a long cache, timed: searchLoops streaming a PC2 file
// (blocks of 512 vertices, on 1 thread and on all cores) against the obvious search it
// replaces, run in the same process on the same cache held whole in memory: every (start,
// cycles) pair compared vertex by vertex in double precision, one frame pair at a time.
// With a cache file, pass 1 on it, and pass 2 on its candidates where it is the sample dress.
// The cache is a swinging ring of VERTICES points with noise, CYCLES cycles of 32 frames.
// Usage: loop_search_bench [VERTICES=5000] [CYCLES=40] [DIR=/tmp]
//        loop_search_bench CACHE.pc2|CACHE.mdd CYCLE_FRAMES   (a real cache: time, candidates)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "crowd/bake/cloth_loop.h"
#include "crowd/bake/loop_search.h"
#include "crowd/support/point_cache.h"
#include "crowd/samples/cloth_caches.h"

using namespace crowd;
using Clock = std::chrono::steady_clock;

namespace {

double seconds(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The same unfiltered distance as pass 1 (position + per-frame velocity, both squared), the
// obvious way: best (start, cycles) by the raw distance at the seam.
double naiveBest(const std::vector<std::vector<glm::vec3>> &f, uint32_t cycle) {
  double best = 1e300;
  const size_t n = f.size();
  for (size_t len = cycle; len + 2 <= n; len += cycle)
    for (size_t s = 0; s + len + 1 < n; ++s) {
      double d = 0.0;
      for (size_t v = 0; v < f[s].size(); ++v) {
        const glm::dvec3 d0 = glm::dvec3(f[s + len][v]) - glm::dvec3(f[s][v]);
        const glm::dvec3 d1 = glm::dvec3(f[s + len + 1][v]) - glm::dvec3(f[s + 1][v]);
        d += glm::dot(d0, d0) + glm::dot(d1 - d0, d1 - d0);
      }
      best = std::min(best, d / double(f[s].size()));
    }
  return best;
}

// Pass 1 on a cache file: its time and every candidate's seam against the yardsticks.
int searchFile(const std::string &path, double cycle) {
  PointCacheReader reader(path, {});
  LoopSearchOptions o;
  o.cycleFrames = cycle;
  const auto t0 = Clock::now();
  const LoopSearch s = searchLoops(
      reader.info().frameCount, reader.info().vertexCount,
      [&](uint32_t f, uint32_t first, uint32_t count, auto &out) {
        reader.read(f, first, count, out);
      },
      o);
  std::printf("%s: %u vertices x %u frames, cycle %.2f frames: pass 1 %.3f s\n", path.c_str(),
              reader.info().vertexCount, reader.info().frameCount, cycle, seconds(t0));
  std::printf("mean per-frame motion %.4g, mean per-frame velocity change %.4g (cache units)\n",
              s.meanMotion, s.meanVelocityChange);
  for (const auto &c : s.candidates)
    std::printf("start %4u  cycles %2u  distance %.3g  seam position jump %.3f x mean motion, "
                "velocity jump %.3f x mean change\n",
                c.start, c.cycles, c.distance, c.positionJump / s.meanMotion,
                c.velocityJump / s.meanVelocityChange);
  if (reader.info().vertexCount != samples::dressVertexCount())
    return 0;
  // Both passes and the verdict where the cache is the sample dress (whose triangles the
  // samples know).
  ClothLoopOptions co;
  co.search = o;
  const LoopChoice loop = chooseLoop(
      reader.info().frameCount, reader.info().vertexCount,
      [&](uint32_t f, uint32_t first, uint32_t count, auto &out) {
        reader.read(f, first, count, out);
      },
      samples::dressIndices(), co);
  std::printf("pass 1 %.3f s, pass 2 (%u views, %d px) %.3f s; in pass 2's order:\n",
              loop.pass1Seconds, co.edges.views, co.edges.pixels, loop.pass2Seconds);
  for (const auto &c : loop.candidates) {
    std::printf("start %4u  cycles %2u  pass-1 rank %u  edge distance per view (px)", c.seam.start,
                c.seam.cycles, c.pass1Rank);
    for (double d : c.edgeDistances)
      std::printf(" %.2f", d);
    std::printf(", sum %.2f\n", c.edgeDistance);
  }
  std::printf("verdict: %s\n", loop.verdict.c_str());
  return 0;
}

} // namespace

int main(int argc, char **argv) {
  if (argc > 2 &&
      (std::string(argv[1]).ends_with(".pc2") || std::string(argv[1]).ends_with(".mdd")))
    return searchFile(argv[1], std::atof(argv[2]));
  const uint32_t vertices = argc > 1 ? uint32_t(std::atoi(argv[1])) : 5000;
  const uint32_t cycles = argc > 2 ? uint32_t(std::atoi(argv[2])) : 40;
  const std::string path = std::string(argc > 3 ? argv[3] : "/tmp") + "/loop_search_bench.pc2";
  const uint32_t cycle = 32, frames = cycles * cycle;
  std::mt19937 rng(1);
  std::normal_distribution<float> noise(0.0f, 0.002f);
  std::vector<std::vector<glm::vec3>> cache(frames, std::vector<glm::vec3>(vertices));
  for (uint32_t f = 0; f < frames; ++f)
    for (uint32_t v = 0; v < vertices; ++v) {
      const float a = 6.2831853f * float(v) / float(vertices), t = 6.2831853f * float(f) / 64.0f;
      cache[f][v] = {0.3f * std::cos(a) + 0.1f * std::sin(t + a) + noise(rng),
                     0.8f - 0.3f * float(v % 50) / 50.0f, 0.3f * std::sin(a) + noise(rng)};
    }
  {
    const auto bytes = encodePointCache(PointCacheFormat::Pc2, cache, 30.0);
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char *>(bytes.data()), std::streamsize(bytes.size()));
  }
  std::printf("cache: %u vertices x %u frames (%u cycles of %u), %.0f MB PC2\n", vertices, frames,
              cycles, cycle, double(frames) * vertices * 12 / 1e6);

  auto t0 = Clock::now();
  const double naive = naiveBest(cache, cycle);
  const double naiveSeconds = seconds(t0);
  cache.clear();
  cache.shrink_to_fit();

  double timed[2] = {};
  LoopSearch result;
  for (int threads : {1, 0}) {
    PointCacheReader reader(path, {});
    LoopSearchOptions o;
    o.cycleFrames = cycle;
    o.threads = threads;
    t0 = Clock::now();
    result = searchLoops(
        frames, vertices,
        [&](uint32_t f, uint32_t first, uint32_t count, auto &out) {
          reader.read(f, first, count, out);
        },
        o);
    timed[threads == 1 ? 0 : 1] = seconds(t0);
  }
  std::remove(path.c_str());
  const auto &best = result.candidates.front();
  std::printf("naive (whole cache in memory, 1 thread): %.3f s, best raw distance %.3g\n",
              naiveSeconds, naive);
  std::printf("searchLoops streaming, 1 thread:         %.3f s (%.1fx faster)\n", timed[0],
              naiveSeconds / timed[0]);
  std::printf("searchLoops streaming, all cores:        %.3f s (%.1fx faster)\n", timed[1],
              naiveSeconds / timed[1]);
  std::printf("best loop: start %u, %u cycles, filtered distance %.3g, position jump %.3g "
              "(mean motion %.3g)\n",
              best.start, best.cycles, best.distance, best.positionJump, result.meanMotion);
  std::printf("held during the search: %u frames x 512 vertices = %.1f MB (cache %.0f MB)\n",
              frames, double(frames) * 512 * 12 / 1e6, double(frames) * vertices * 12 / 1e6);
  return 0;
}
