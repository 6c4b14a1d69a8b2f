// Which body faces a worn outfit hides in every frame, by ray casting against a CGAL AABB tree of
// the skinned body and garments (see outfit_bake.h).
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <tuple>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include "crowd/bake/evaluate.h"
#include "crowd/bake/outfit_bake.h"
#include "crowd/bake/parallel.h"
#include "crowd/formats/error.h"
#include "ray_crossing.h"

namespace crowd {

namespace {

using K = CGAL::Simple_cartesian<double>;
using Triangle = K::Triangle_3;
using Tree = CGAL::AABB_tree<
    CGAL::AABB_traits<K, CGAL::AABB_triangle_primitive<K, std::vector<Triangle>::const_iterator>>>;

// Per occluder (an index into `occluders`), the occluders across its edges (by vertex index;
// kNone where the edge is open, or where a third face shares it).
std::vector<std::array<uint32_t, 3>> edgeNeighbours(const std::vector<uint32_t> &idx,
                                                    const std::vector<uint32_t> &occluders) {
  constexpr uint32_t kNone = UINT32_MAX;
  std::vector<std::array<uint32_t, 3>> across(occluders.size(), {kNone, kNone, kNone});
  std::map<std::pair<uint32_t, uint32_t>, std::pair<uint32_t, int>> first; // edge -> (face, side)
  for (uint32_t k = 0; k < occluders.size(); ++k)
    for (int e = 0; e < 3; ++e) {
      const auto [a, b] =
          std::minmax(idx[3 * occluders[k] + e], idx[3 * occluders[k] + (e + 1) % 3]);
      const auto [it, fresh] = first.emplace(std::pair(a, b), std::pair(k, e));
      if (!fresh && across[it->second.first][it->second.second] == kNone) {
        across[it->second.first][it->second.second] = k;
        across[k][e] = it->second.first;
      }
    }
  return across;
}

// Directions over the hemisphere around +Z in rings: `azimuths` of them on the lowest ring, 1
// degree above the horizon, fewer (by the cosine) on higher rings, ending at the pole. Ring
// elevations grow quadratically, so grazing directions are dense: a gap between body and
// garment (a sleeve's opening, a collar) is often seen only at a few degrees. The pole, the
// likeliest to escape, comes first.
std::vector<glm::dvec3> hemisphere(uint32_t azimuths) {
  const uint32_t rings = std::max(2u, azimuths / 3);
  std::vector<glm::dvec3> d{{0, 0, 1}};
  for (uint32_t k = rings; k-- > 0;) {
    const double s = double(k) / double(rings);
    const double el = glm::radians(1.0 + 89.0 * s * s);
    const auto n = std::max(1u, uint32_t(std::lround(azimuths * std::cos(el))));
    for (uint32_t a = 0; a < n; ++a) {
      const double phi = 2 * M_PI * (a + 0.5 * (k % 2)) / n;
      d.emplace_back(std::cos(el) * std::cos(phi), std::cos(el) * std::sin(phi), std::sin(el));
    }
  }
  return d;
}

constexpr uint32_t kNone = UINT32_MAX;

// Occluders: the body and the worn, opaque garments.
std::vector<uint32_t> occludersOf(const SkinnedMesh &mesh, uint32_t bodyTriangles,
                                  const std::vector<size_t> &garmentParts) {
  std::vector<uint32_t> occluders;
  for (uint32_t t = 0; t < bodyTriangles; ++t)
    occluders.push_back(t);
  for (size_t p : garmentParts) {
    const auto &part = mesh.parts[p];
    if (part.seeThrough)
      continue;
    for (uint32_t t = part.firstIndex / 3; t < (part.firstIndex + part.indexCount) / 3; ++t)
      occluders.push_back(t);
  }
  return occluders;
}

// One frame's occluders posed, in a CGAL tree and as crossing() reads them, and the answer to
// whether a ray is blocked, remembering by what: the guesses first, then the occluders within
// kSteps edge steps of its last blocker (the ray slid off it onto a neighbour; where it has none
// yet, of its neighbours' first), then the tree. Every answer is the tree's: the guesses only
// spare it the query (a tree query costs about what 100 of these tests do; within 3 steps was
// the fastest, docs/bakes/outfits.md).
class FrameOccluders {
public:
  FrameOccluders(const std::vector<glm::dvec3> &p, const std::vector<uint32_t> &idx,
                 const std::vector<uint32_t> &occluders,
                 const std::vector<std::array<uint32_t, 3>> &across, double nudge)
      : across_(across), soupOf_(occluders.size()) {
    auto point = [&](uint32_t v) { return K::Point_3(p[v].x, p[v].y, p[v].z); };
    glm::dvec3 low = p[0], high = p[0]; // every ray starts and every occluder lies in this box
    for (const glm::dvec3 &x : p)
      low = glm::min(low, x), high = glm::max(high, x);
    const double span = glm::length(high - low) + 2 * nudge; // the farthest a ray starts
    for (uint32_t k = 0; k < occluders.size(); ++k) {
      const uint32_t t = occluders[k];
      Triangle tri(point(idx[3 * t]), point(idx[3 * t + 1]), point(idx[3 * t + 2]));
      soupOf_[k] = tri.is_degenerate() ? kNone : uint32_t(soup_.size());
      if (!tri.is_degenerate()) {
        soup_.push_back(tri);
        soupEdges_.push_back(
            outfit::edgesOf(p[idx[3 * t]], p[idx[3 * t + 1]], p[idx[3 * t + 2]], span));
        occluderOf_.push_back(k);
      }
    }
    tree_.insert(soup_.begin(), soup_.end());
    tree_.build();
  }

  bool blocked(const glm::dvec3 &o, const glm::dvec3 &w, uint32_t &last,
               std::initializer_list<uint32_t> guesses) const {
    constexpr int kSteps = 3;
    // CGAL's ray, made where CGAL is asked: for about 1.5% of the sample dress's rays.
    std::optional<K::Ray_3> cgalRay;
    const auto ray = [&]() -> const K::Ray_3 & {
      if (!cgalRay)
        cgalRay.emplace(K::Point_3(o.x, o.y, o.z), K::Vector_3(w.x, w.y, w.z));
      return *cgalRay;
    };
    const auto blocks = [&](uint32_t k) {
      if (k == kNone || soupOf_[k] == kNone)
        return false;
      const outfit::Crossing c = outfit::crossing(o, w, soupEdges_[soupOf_[k]]);
      return c == outfit::Crossing::kYes ||
             (c == outfit::Crossing::kUnsure && CGAL::do_intersect(ray(), soup_[soupOf_[k]]));
    };
    for (auto g = guesses.begin(); g != guesses.end(); ++g)
      if (std::find(guesses.begin(), g, *g) == g && blocks(*g)) {
        last = *g;
        return true;
      }
    uint32_t seed = kNone; // its last blocker, else its neighbours'
    for (auto g = guesses.begin(); g != guesses.end() && seed == kNone; ++g)
      seed = *g;
    if (seed != kNone) { // nearest first, each occluder once
      std::array<uint32_t, 64> near{seed};
      size_t n = 1, from = 0;
      for (int step = 0; step < kSteps; ++step) {
        const size_t to = n;
        for (size_t i = from; i < to; ++i)
          for (uint32_t k : across_[near[i]])
            if (k != kNone && n < near.size() &&
                std::find(near.data(), near.data() + n, k) == near.data() + n) {
              near[n++] = k; // searched from, but tested only if not a guess (all missed)
              if (std::find(guesses.begin(), guesses.end(), k) == guesses.end() && blocks(k)) {
                last = k;
                return true;
              }
            }
        from = to;
      }
    }
    const auto hit = tree_.any_intersected_primitive(ray());
    if (!hit)
      return false;
    last = occluderOf_[size_t(*hit - soup_.cbegin())];
    return true;
  }

private:
  const std::vector<std::array<uint32_t, 3>> &across_;
  std::vector<Triangle> soup_;
  std::vector<outfit::Edges> soupEdges_;      // soup_'s triangles as crossing() reads them
  std::vector<uint32_t> soupOf_, occluderOf_; // occluder <-> soup triangle
  Tree tree_;
};

// The rays a body face casts: from `points` points on it, nudged off it, over the hemisphere.
struct Rays {
  const std::vector<glm::dvec3> &directions;
  uint32_t points;
  double nudge, ground, reach; // ground: the plane's height (INFINITY: none); reach: its extent
};

// Whether face t (wound to its outward side `side`) sees out in pose p along any ray; `last`:
// its rays' blockers of the last frame, updated.
bool faceSeen(const std::vector<glm::dvec3> &p, const std::vector<uint32_t> &idx, uint32_t t,
              double side, const Rays &rays, const FrameOccluders &occluders, uint32_t *last) {
  static const glm::dvec3 weights[4] = {{1.0 / 3, 1.0 / 3, 1.0 / 3},
                                        {4.0 / 6, 1.0 / 6, 1.0 / 6},
                                        {1.0 / 6, 4.0 / 6, 1.0 / 6},
                                        {1.0 / 6, 1.0 / 6, 4.0 / 6}};
  const auto &directions = rays.directions;
  const glm::dvec3 a = p[idx[3 * t]], b = p[idx[3 * t + 1]], c = p[idx[3 * t + 2]];
  glm::dvec3 n = glm::cross(b - a, c - a) * side;
  const double len = glm::length(n);
  if (!(len > 1e-14)) // degenerate in this pose: nothing to decide, keep it (conservative)
    return true;
  n /= len;
  const glm::dvec3 u = glm::normalize(std::abs(n.x) < 0.9 ? glm::cross(n, glm::dvec3(1, 0, 0))
                                                          : glm::cross(n, glm::dvec3(0, 1, 0)));
  const glm::dvec3 v = glm::cross(n, u);
  for (uint32_t k = 0; k < rays.points; ++k) {
    const glm::dvec3 q = a * weights[k].x + b * weights[k].y + c * weights[k].z + n * rays.nudge;
    for (size_t j = 0; j < directions.size(); ++j) {
      const glm::dvec3 &d = directions[j];
      const glm::dvec3 w = u * d.x + v * d.y + n * d.z;
      // The ground, analytically (in the tree, its huge triangles would slow every query).
      if (w.y < 0 && q.y >= rays.ground && q.y - rays.ground < -w.y * rays.reach)
        continue;
      // Its own blocker of the last frame, then its neighbours': the previous direction's
      // (this frame), the next one's (the last frame) and the previous point's.
      const size_t r = k * directions.size() + j;
      const uint32_t before = j > 0 ? last[r - 1] : kNone;
      const uint32_t after = j + 1 < directions.size() ? last[r + 1] : kNone;
      const uint32_t other = k > 0 ? last[r - directions.size()] : kNone;
      if (!occluders.blocked(q, w, last[r], {last[r], before, after, other}))
        return true;
    }
  }
  return false;
}

// Safety ring: faces sharing a vertex position with a visible face stay visible, `ring` times.
void addSafetyRing(const SkinnedMesh &mesh, uint32_t bodyTriangles, uint32_t ring,
                   std::vector<uint8_t> &hidden) {
  const auto &idx = mesh.indices;
  std::vector<uint32_t> weld(mesh.vertexCount());
  std::vector<uint32_t> order(mesh.vertexCount());
  for (uint32_t v = 0; v < order.size(); ++v)
    order[v] = v;
  auto key = [&](uint32_t v) {
    const auto &q = mesh.positions[v];
    return std::make_tuple(q.x, q.y, q.z);
  };
  std::sort(order.begin(), order.end(),
            [&](uint32_t x, uint32_t y) { return key(x) != key(y) ? key(x) < key(y) : x < y; });
  for (size_t i = 0; i < order.size(); ++i)
    weld[order[i]] = i && key(order[i]) == key(order[i - 1]) ? weld[order[i - 1]] : order[i];
  for (uint32_t step = 0; step < ring; ++step) {
    std::vector<uint8_t> touched(mesh.vertexCount(), 0);
    for (uint32_t t = 0; t < bodyTriangles; ++t)
      if (!hidden[t])
        for (int k = 0; k < 3; ++k)
          touched[weld[idx[3 * t + k]]] = 1;
    for (uint32_t t = 0; t < bodyTriangles; ++t)
      for (int k = 0; k < 3; ++k)
        if (touched[weld[idx[3 * t + k]]])
          hidden[t] = 0;
  }
}

} // namespace

std::vector<std::pair<const AnimationClip *, double>> outfitFrames(const Character &c, double fps,
                                                                   uint32_t step) {
  std::vector<std::pair<const AnimationClip *, double>> out;
  for (const auto &clip : c.clips) {
    const double duration = clip.end - clip.start;
    const auto intervals = uint32_t(duration > 0 ? std::max(1.0, std::round(duration * fps)) : 0);
    for (uint32_t i = 0; i <= intervals; ++i)
      if (i % step == 0 || i == intervals)
        out.emplace_back(&clip, clip.start + (intervals ? duration * i / intervals : 0.0));
  }
  if (out.empty())
    out.emplace_back(nullptr, 0.0); // no clip: the rest pose
  return out;
}

// Every frame, each body face still hidden casts its rays; one that sees out is visible and
// leaves the candidates. Per (face, point, direction) the occluder that blocked that ray in the
// last frame that cast it goes first: bodies move little between frames, so it (or the one that
// blocked a neighbouring ray) usually blocks the ray again (sample dress: 98% of the rays).
std::vector<uint8_t> hiddenBodyFaces(const Character &merged, uint32_t bodyTriangles,
                                     const std::vector<size_t> &garmentParts,
                                     const VisibilityOptions &o,
                                     const std::vector<PlacedLoop> &loops) {
  if (o.rays == 0 || o.rays > 4096 || (o.points != 1 && o.points != 4) || o.frameStep == 0 ||
      !(o.fps > 0))
    throw Error("visibility: rays must be in 1..4096, points 1 or 4, frame step >= 1, fps > 0");
  const auto &mesh = merged.mesh;
  const auto &idx = mesh.indices;
  const std::vector<uint32_t> occluders = occludersOf(mesh, bodyTriangles, garmentParts);
  // Outward side of each body face as drawn: the side its vertex normals point to.
  const std::vector<double> side = outwardSides(merged);
  const auto directions = hemisphere(o.rays);
  Rays rays{directions, o.points, 1e-4 * restDiagonal(merged), INFINITY,
            100 * restDiagonal(merged)};
  std::vector<uint8_t> hidden(bodyTriangles, 1);
  std::vector<uint32_t> candidates(bodyTriangles);
  for (uint32_t t = 0; t < bodyTriangles; ++t)
    candidates[t] = t;
  const auto frames = outfitPoses(merged, o.fps, o.frameStep, loops, o.loopFrames);
  // The ground: a plane under the body's lowest point over every tested frame, as wide as the
  // ground rays can reach (100 body diagonals).
  if (o.ground)
    for (const auto &pose : frames) {
      const auto p = posed(merged, pose);
      for (uint32_t i = 0; i < bodyTriangles * 3; ++i)
        rays.ground = std::min(rays.ground, p[idx[i]].y);
    }
  const size_t raysPerFace = size_t(o.points) * directions.size();
  std::vector<uint32_t> blocker(size_t(bodyTriangles) * raysPerFace, kNone);
  const auto across = edgeNeighbours(idx, occluders);
  for (const auto &pose : frames) {
    if (candidates.empty())
      break;
    const auto p = posed(merged, pose);
    const FrameOccluders frame(p, idx, occluders, across, rays.nudge);
    std::vector<uint8_t> seen(candidates.size(), 0);
    parallelFor(candidates.size(), o.threads, [&](size_t i) {
      const uint32_t t = candidates[i];
      seen[i] = faceSeen(p, idx, t, side[t], rays, frame, &blocker[size_t(t) * raysPerFace]);
    });
    std::vector<uint32_t> left;
    for (size_t i = 0; i < candidates.size(); ++i) {
      if (seen[i])
        hidden[candidates[i]] = 0;
      else
        left.push_back(candidates[i]);
    }
    candidates.swap(left);
  }
  if (o.ring > 0)
    addSafetyRing(mesh, bodyTriangles, o.ring, hidden);
  return hidden;
}

} // namespace crowd
