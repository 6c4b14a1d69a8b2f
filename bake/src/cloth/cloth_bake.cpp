#include "crowd/bake/cloth_bake.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include "crowd/bake/anim_bake.h"
#include "crowd/bake/evaluate.h"
#include "crowd/formats/error.h"

namespace crowd {

namespace {

using K = CGAL::Simple_cartesian<double>;
using Triangle = K::Triangle_3;
using Tree = CGAL::AABB_tree<
    CGAL::AABB_traits<K, CGAL::AABB_triangle_primitive<K, std::vector<Triangle>::const_iterator>>>;

// The garment's triangles over the cache's vertices (`garment`: outfit vertex ids, ascending).
std::vector<uint32_t> cacheIndices(const Character &outfit, const std::string &name,
                                   const std::vector<uint32_t> &garment) {
  std::vector<uint32_t> out;
  for (const auto &part : outfit.mesh.parts)
    if (part.name == name)
      for (uint32_t i = part.firstIndex; i < part.firstIndex + part.indexCount; ++i) {
        const uint32_t v = outfit.mesh.indices[i];
        out.push_back(
            uint32_t(std::lower_bound(garment.begin(), garment.end(), v) - garment.begin()));
      }
  return out;
}

// The body skinned at one frame, in the root frame, with each face's outward side (the side
// its vertex normals point to, as the outfit bake's visibility decides it).
class PosedBody {
public:
  // `sides`: outwardSides(body), the same at every frame.
  PosedBody(const Character &body, const std::vector<glm::dvec3> &positions,
            const std::vector<double> &sides) {
    const auto &idx = body.mesh.indices;
    for (size_t t = 0; t + 2 < idx.size(); t += 3) {
      const glm::dvec3 a = positions[idx[t]], b = positions[idx[t + 1]], c = positions[idx[t + 2]];
      Triangle tri({a.x, a.y, a.z}, {b.x, b.y, b.z}, {c.x, c.y, c.z});
      if (tri.is_degenerate())
        continue;
      outward_.push_back(sides[t / 3]);
      soup_.push_back(tri);
    }
    tree_.insert(soup_.begin(), soup_.end());
    tree_.build();
    tree_.accelerate_distance_queries();
  }
  bool empty() const { return soup_.empty(); }
  // The closest body point to p and the outward unit normal of its face.
  std::pair<glm::dvec3, glm::dvec3> closest(const glm::dvec3 &p) const {
    const auto [q, prim] = tree_.closest_point_and_primitive(K::Point_3(p.x, p.y, p.z));
    const size_t t = size_t(prim - soup_.begin());
    const auto n = CGAL::normal(soup_[t][0], soup_[t][1], soup_[t][2]);
    glm::dvec3 nn(n.x(), n.y(), n.z());
    nn = glm::normalize(nn) * outward_[t];
    return {glm::dvec3(q.x(), q.y(), q.z()), nn};
  }
  bool inside(const glm::dvec3 &p) const {
    const auto [q, n] = closest(p);
    return glm::dot(p - q, n) < 0.0;
  }

private:
  std::vector<Triangle> soup_;
  std::vector<double> outward_;
  Tree tree_;
};

} // namespace

namespace {

using Frames = std::vector<std::vector<glm::vec3>>;

// The cross-fade's length in frames: none where the verdict accepts the seam; else the option's,
// or the verdict's where the option asks (-1), cut to what fits before the loop's start and in
// half of it. A cut or a hard cut is a warning.
uint32_t chooseBlend(ClothBakeResult &r, const ClothBakeOptions &options, uint32_t start,
                     uint32_t length, Reporter &reporter) {
  if (r.loop.acceptable)
    return 0;
  uint32_t blend = options.blend < 0 ? r.loop.blendFrames : uint32_t(options.blend);
  const uint32_t fits = std::min(start, length / 2);
  if (blend > fits) {
    r.blendClamped = true;
    reporter.warn("cloth_blend_clamped", "the cross-fade of " + std::to_string(blend) +
                                             " frames is cut to " + std::to_string(fits) +
                                             " (half the loop, or the frames before its start)");
    blend = fits;
  }
  if (blend == 0)
    reporter.warn("cloth_hard_cut",
                  "the seam is not acceptable but plays as a hard cut: " + r.loop.verdict);
  return blend;
}

// Moves the blended frame's vertices that the cross-fade took inside the body (posed at
// `cacheFrame`, in the root's frame) out to its surface plus `margin`; `before` is the frame
// as simulated, whose own vertices inside the body stay. Counts them in `r`.
void pushOutOfBody(const Character &body, const AnimationClip &clip, uint32_t cacheFrame,
                   double fps, const std::vector<double> &sides,
                   const std::vector<glm::vec3> &before, double margin, std::vector<glm::vec3> &out,
                   ClothBakeResult &r) {
  const glm::dmat4 toRoot = toRootFrame(body, clip, cacheFrame, fps);
  auto posed = posedPositions(body, &clip, cacheFrameTime(clip, cacheFrame, fps));
  for (auto &p : posed)
    p = glm::dvec3(toRoot * glm::dvec4(p, 1.0));
  const PosedBody b(body, posed, sides);
  if (b.empty())
    return;
  for (size_t v = 0; v < out.size(); ++v) {
    const glm::dvec3 p(out[v]);
    if (!b.inside(p) || b.inside(glm::dvec3(before[v])))
      continue; // outside, or already inside before the blend (the simulation's own)
    const auto [q, normal] = b.closest(p);
    const glm::dvec3 moved = q + normal * margin;
    const double mm = glm::length(moved - p) * r.mmPerUnit;
    out[v] = glm::vec3(moved);
    ++r.pushedVertices;
    r.pushMaxMm = std::max(r.pushMaxMm, mm);
    r.pushMeanMm += mm;
  }
}

// The loop's `length` frames from cache frame `start`, its last `blend` cross-faded into the
// frames before `start` and pushed out of the body where the fade took them in.
Frames blendedLoop(const ClothFrames &frames, uint32_t start, uint32_t length, uint32_t blend,
                   uint32_t n, const Character &body, const AnimationClip &clip, double fps,
                   double margin, ClothBakeResult &r) {
  // x[i]: cache frame start - blend + i; the loop's frame f is x[blend + f].
  Frames x(blend + length);
  for (uint32_t i = 0; i < x.size(); ++i)
    frames(start - blend + i, 0, n, x[i]);
  Frames loopFrames(x.begin() + blend, x.end());
  const bool push = blend > 0 && !body.mesh.indices.empty();
  const std::vector<double> sides = push ? outwardSides(body) : std::vector<double>();
  for (uint32_t j = 0; j < blend; ++j) {
    const uint32_t f = length - blend + j;
    const float w = float(j + 1) / float(blend + 1);
    auto &out = loopFrames[f];
    for (uint32_t v = 0; v < n; ++v)
      out[v] = glm::mix(x[blend + f][v], x[j][v], w);
    if (push)
      pushOutOfBody(body, clip, start + f, fps, sides, x[blend + f], margin, out, r);
  }
  if (r.pushedVertices)
    r.pushMeanMm /= r.pushedVertices;
  return loopFrames;
}

// The frames quantised to 16 bits per axis over the loop's box into the chunk, and the
// quantisation's error in `r`.
void quantiseLoop(const Frames &loopFrames, ClothBakeResult &r) {
  glm::vec3 lo3(INFINITY), hi3(-INFINITY);
  for (const auto &frame : loopFrames)
    for (const auto &p : frame) {
      lo3 = glm::min(lo3, p);
      hi3 = glm::max(hi3, p);
    }
  pack::ClothLoop &c = r.chunk;
  for (int k = 0; k < 3; ++k) {
    c.origin[size_t(k)] = lo3[k];
    c.step[size_t(k)] = (hi3[k] - lo3[k]) / 65535.0f;
  }
  const size_t length = loopFrames.size(), n = loopFrames.empty() ? 0 : loopFrames[0].size();
  c.positions.reserve(length * n * 3);
  for (const auto &frame : loopFrames)
    for (const auto &p : frame)
      for (int k = 0; k < 3; ++k) {
        const float s = c.step[size_t(k)];
        const float q = s > 0 ? std::round((p[k] - lo3[k]) / s) : 0.0f;
        c.positions.push_back(uint16_t(std::clamp(q, 0.0f, 65535.0f)));
      }
  double sum = 0.0;
  for (uint32_t f = 0; f < length; ++f)
    for (uint32_t v = 0; v < n; ++v) {
      const auto q = c.position(f, v);
      const double mm =
          glm::length(glm::dvec3(q[0], q[1], q[2]) - glm::dvec3(loopFrames[f][v])) * r.mmPerUnit;
      r.quantMaxMm = std::max(r.quantMaxMm, mm);
      sum += mm;
    }
  r.quantMeanMm = sum / (double(length) * n);
}

} // namespace

ClothBakeResult bakeClothLoop(const Character &body, const Character &outfit,
                              const std::string &outfitName, const std::string &garment,
                              const std::string &clipName, const std::string &cachePath,
                              const InputPolicy &policy, const ClothBakeOptions &options,
                              Reporter &reporter) {
  options.validate();
  const auto t0 = std::chrono::steady_clock::now();
  ClothBakeResult r;
  const AnimationClip &clip = findClip(body, clipName);
  if (!(clip.end > clip.start))
    throw Error("clip '" + clipName + "' has no duration: a cloth loop needs a cycle");
  const std::vector<uint32_t> garmentIds = garmentVertices(outfit, garment);
  PointCacheReader cache(cachePath, policy.bound());
  const double fps = cacheFps(cache, options.cache);
  checkGarment(cache, outfit, garmentIds, clip, options.cache);
  r.mmPerUnit = millimetresPerUnit(body);
  r.rate = fitFrameRate(cache, outfit, garmentIds, clip, fps);
  if (r.rate.mismatch) {
    char text[256];
    std::snprintf(text, sizeof text,
                  "the garment's body-bound vertices follow the body at %.3g fps (%.3g mm off on "
                  "average), not at the %.3g fps read (%.3g mm): is the cache's frame rate "
                  "(--fps, or the manifest's \"fps\") right?",
                  r.rate.bestRate, r.rate.bestResidual * r.mmPerUnit, fps,
                  r.rate.residual * r.mmPerUnit);
    reporter.warn("cloth_fps_mismatch", text);
  }
  const uint32_t n = cache.info().vertexCount;
  const ClothFrames frames = rootFrames(cache, body, clip, fps);
  ClothLoopOptions lo = options.loop;
  lo.search.cycleFrames = (clip.end - clip.start) * fps;
  reporter.step("cloth loop: searching " + std::to_string(cache.info().frameCount) +
                " cache frames for a cycle of " + clipName);
  r.loop =
      chooseLoop(cache.info().frameCount, n, frames, cacheIndices(outfit, garment, garmentIds), lo);
  const LoopCandidate &seam = r.loop.candidates.front().seam;
  const uint32_t start = seam.start, length = seam.length;
  const uint32_t blend = chooseBlend(r, options, start, length, reporter);
  const Frames loopFrames = blendedLoop(frames, start, length, blend, n, body, clip, fps,
                                        options.pushMarginMm / r.mmPerUnit, r);

  pack::ClothLoop &c = r.chunk;
  c.outfit = outfitName;
  c.garment = garment;
  c.clip = clipName;
  c.fps = float(fps);
  c.cycles = seam.cycles;
  c.cacheStart = start;
  c.blendFrames = blend;
  if (outfit.mesh.sources.size() != outfit.mesh.vertexCount())
    throw Error("outfit '" + outfitName +
                "' has no vertex sources to name the garment's vertices by");
  std::vector<pack::VertexSource> sources;
  for (uint32_t v : garmentIds)
    sources.push_back(outfit.mesh.sources[v]);
  c.sources = pack::SourceMap::of(sources);
  quantiseLoop(loopFrames, r);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

} // namespace crowd
