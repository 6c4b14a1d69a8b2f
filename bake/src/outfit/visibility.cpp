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

std::vector<uint8_t> hiddenBodyFaces(const Character &merged, uint32_t bodyTriangles,
                                     const std::vector<size_t> &garmentParts,
                                     const VisibilityOptions &o,
                                     const std::vector<PlacedLoop> &loops) {
  if (o.rays == 0 || o.rays > 4096 || (o.points != 1 && o.points != 4) || o.frameStep == 0 ||
      !(o.fps > 0))
    throw Error("visibility: rays must be in 1..4096, points 1 or 4, frame step >= 1, fps > 0");
  const auto &mesh = merged.mesh;
  const auto &idx = mesh.indices;
  // Occluders: the body and the worn, opaque garments.
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
  // Outward side of each body face as drawn: the side its vertex normals point to.
  const std::vector<double> side = outwardSides(merged);
  const auto directions = hemisphere(o.rays);
  const double nudge = 1e-4 * restDiagonal(merged);
  const glm::dvec3 weights[4] = {{1.0 / 3, 1.0 / 3, 1.0 / 3},
                                 {4.0 / 6, 1.0 / 6, 1.0 / 6},
                                 {1.0 / 6, 4.0 / 6, 1.0 / 6},
                                 {1.0 / 6, 1.0 / 6, 4.0 / 6}};

  std::vector<uint8_t> hidden(bodyTriangles, 1);
  std::vector<uint32_t> candidates(bodyTriangles);
  for (uint32_t t = 0; t < bodyTriangles; ++t)
    candidates[t] = t;
  const auto frames = outfitPoses(merged, o.fps, o.frameStep, loops, o.loopFrames);
  // The ground: a plane under the body's lowest point over every tested frame, as wide as the
  // ground rays can reach (100 body diagonals).
  double ground = INFINITY;
  if (o.ground)
    for (const auto &pose : frames) {
      const auto p = posed(merged, pose);
      for (uint32_t i = 0; i < bodyTriangles * 3; ++i)
        ground = std::min(ground, p[idx[i]].y);
    }
  const double reach = 100 * restDiagonal(merged);
  // Per (body face, point, direction): the occluder that blocked that ray in the last frame that
  // cast it (kNone: none yet). Bodies move little between frames, so the same triangle, or the
  // one that blocked a neighbouring ray, usually blocks the ray again: tested alone first (the
  // predicate the tree's own test uses, after a quick test that is sure of most answers), they
  // answer most rays without a tree query (sample dress: 98% of them). When none blocks, the tree
  // answers, so every answer is the tree's: the hidden faces are the same bits as without the
  // cache.
  constexpr uint32_t kNone = UINT32_MAX;
  const size_t raysPerFace = size_t(o.points) * directions.size();
  std::vector<uint32_t> blocker(size_t(bodyTriangles) * raysPerFace, kNone);
  const auto across = edgeNeighbours(idx, occluders);
  std::vector<Triangle> soup;
  std::vector<outfit::Edges> soupEdges; // soup's triangles as crossing() reads them
  std::vector<uint32_t> soupOf(occluders.size()), occluderOf; // occluder <-> soup triangle
  for (const auto &pose : frames) {
    if (candidates.empty())
      break;
    const auto p = posed(merged, pose);
    auto point = [&](uint32_t v) { return K::Point_3(p[v].x, p[v].y, p[v].z); };
    soup.clear();
    soupEdges.clear();
    occluderOf.clear();
    glm::dvec3 low = p[0], high = p[0]; // every ray starts and every occluder lies in this box
    for (const glm::dvec3 &x : p)
      low = glm::min(low, x), high = glm::max(high, x);
    const double span = glm::length(high - low) + 2 * nudge; // the farthest a ray starts
    for (uint32_t k = 0; k < occluders.size(); ++k) {
      const uint32_t t = occluders[k];
      Triangle tri(point(idx[3 * t]), point(idx[3 * t + 1]), point(idx[3 * t + 2]));
      soupOf[k] = tri.is_degenerate() ? kNone : uint32_t(soup.size());
      if (!tri.is_degenerate()) {
        soup.push_back(tri);
        soupEdges.push_back(
            outfit::edgesOf(p[idx[3 * t]], p[idx[3 * t + 1]], p[idx[3 * t + 2]], span));
        occluderOf.push_back(k);
      }
    }
    Tree tree(soup.begin(), soup.end());
    tree.build();
    // Whether the ray is blocked, remembering by what: the guesses first, then the occluders
    // within kSteps edge steps of its last blocker (the ray slid off it onto a neighbour; where
    // it has none yet, of its neighbours' first), then the tree. A tree query costs
    // about what 100 of these tests do: within 3 steps, the sample dress's visibility took
    // 6.0 -> 5.7 s (2 steps before; 4: the same, 6: 6.0 s), and from a neighbour's blocker
    // where the ray has none (the first frame) 5.4 s.
    constexpr int kSteps = 3;
    const auto blocked = [&](const glm::dvec3 &o, const glm::dvec3 &w, uint32_t &last,
                             std::initializer_list<uint32_t> guesses) {
      // CGAL's ray, made where CGAL is asked: for about 1.5% of the sample dress's rays.
      std::optional<K::Ray_3> cgalRay;
      const auto ray = [&]() -> const K::Ray_3 & {
        if (!cgalRay)
          cgalRay.emplace(K::Point_3(o.x, o.y, o.z), K::Vector_3(w.x, w.y, w.z));
        return *cgalRay;
      };
      const auto blocks = [&](uint32_t k) {
        if (k == kNone || soupOf[k] == kNone)
          return false;
        const outfit::Crossing c = outfit::crossing(o, w, soupEdges[soupOf[k]]);
        return c == outfit::Crossing::kYes ||
               (c == outfit::Crossing::kUnsure && CGAL::do_intersect(ray(), soup[soupOf[k]]));
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
            for (uint32_t k : across[near[i]])
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
      const auto hit = tree.any_intersected_primitive(ray());
      if (!hit)
        return false;
      last = occluderOf[size_t(*hit - soup.cbegin())];
      return true;
    };
    std::vector<uint8_t> seen(candidates.size(), 0);
    parallelFor(candidates.size(), o.threads, [&](size_t i) {
      const uint32_t t = candidates[i];
      const glm::dvec3 a = p[idx[3 * t]], b = p[idx[3 * t + 1]], c = p[idx[3 * t + 2]];
      glm::dvec3 n = glm::cross(b - a, c - a) * side[t];
      const double len = glm::length(n);
      if (!(len > 1e-14)) { // degenerate in this pose: nothing to decide, keep it (conservative)
        seen[i] = 1;
        return;
      }
      n /= len;
      const glm::dvec3 u = glm::normalize(std::abs(n.x) < 0.9 ? glm::cross(n, glm::dvec3(1, 0, 0))
                                                              : glm::cross(n, glm::dvec3(0, 1, 0)));
      const glm::dvec3 v = glm::cross(n, u);
      uint32_t *last = &blocker[size_t(t) * raysPerFace];
      for (uint32_t k = 0; k < o.points && !seen[i]; ++k) {
        const glm::dvec3 q = a * weights[k].x + b * weights[k].y + c * weights[k].z + n * nudge;
        for (size_t j = 0; j < directions.size(); ++j) {
          const glm::dvec3 &d = directions[j];
          const glm::dvec3 w = u * d.x + v * d.y + n * d.z;
          // The ground, analytically (in the tree, its huge triangles would slow every query).
          if (w.y < 0 && q.y >= ground && q.y - ground < -w.y * reach)
            continue;
          // Its own blocker of the last frame, then its neighbours': the previous direction's
          // (this frame), the next one's (the last frame) and the previous point's.
          const size_t r = k * directions.size() + j;
          const uint32_t before = j > 0 ? last[r - 1] : kNone;
          const uint32_t after = j + 1 < directions.size() ? last[r + 1] : kNone;
          const uint32_t other = k > 0 ? last[r - directions.size()] : kNone;
          if (!blocked(q, w, last[r], {last[r], before, after, other})) {
            seen[i] = 1;
            break;
          }
        }
      }
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

  // Safety ring: faces sharing a vertex position with a visible face stay visible.
  if (o.ring > 0) {
    std::vector<uint32_t> weld(mesh.vertexCount());
    {
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
    }
    for (uint32_t step = 0; step < o.ring; ++step) {
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
  return hidden;
}

} // namespace crowd
