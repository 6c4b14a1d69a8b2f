#include "crowd/bake/lod_bake.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "cost_queue.h"
#include "crowd/bake/character.h"
#include "crowd/bake/evaluate.h"
#include "crowd/formats/error.h"
#include "face_lists.h"
#include "fan_mesh.h"
#include "float_key.h"
#include "pose_quadrics.h"
#include "refusals.h"

// Why by hand, not OpenMesh's half-edge collapse: on flat arrays the whole collapse order runs
// 2.2 times faster on the sample humanoid in the bind pose, 1.7 times with 16 poses (OpenMesh's
// took 2.7 us a triangle before any pose was costed), and meshoptimizer, the fast peer, returns
// index buffers at given counts, not the order of every collapse with its cost that the pack
// stores.
namespace crowd {
namespace {

// A collapse of `from` into `to`, valid while neither vertex has changed since: stamps never go
// down, so their sum is the one it was pushed with exactly where neither moved on. Its cost, or
// until `exact` a lower bound of it (PoseQuadrics::bound). 20 bytes with the queue's link; with
// a stamp each, 24 (lod_bench's 1M grid: peak +373 -> +352 MB).
struct Candidate {
  float cost; // as the pack stores it; the queue's buckets hold fewer bits
  uint32_t from, to;
  uint32_t stamps : 30;         // each stamp <= the collapses < 2^29 (Refusals): the sum fits
  uint32_t exact : 1, pair : 1; // pair: the other way (to -> from) is not queued yet
};

using lod::Block;

// A vertex's neighbour w: the live faces it shares with the vertex (1: an open edge between
// them), the first two of them in the vertex's list and the render vertices of both ends in the
// first; `special` once the ring is built: the edge is open, or a seam (the first two faces use
// other render vertices for an end).
struct Neighbour {
  uint32_t v, faces, first, second, renderSelf, renderOther;
  bool special;
};
// v's neighbours in the order its faces first reach them, with each one's place in `around`
// (1 + its index; 0: not a neighbour): a lookup a corner, not a search of `around`.
class Ring {
public:
  explicit Ring(size_t vertices) : slot_(vertices, 0) {}
  std::vector<Neighbour> around;
  void clear() {
    for (const Neighbour &n : around)
      slot_[n.v] = 0;
    around.clear();
  }
  Neighbour *find(uint32_t w) { return slot_[w] ? &around[slot_[w] - 1] : nullptr; }
  void add(const Neighbour &n) {
    around.push_back(n);
    slot_[n.v] = uint32_t(around.size());
  }
  uint32_t count(uint32_t w) const { return slot_[w] ? around[slot_[w] - 1].faces : 0; }

private:
  std::vector<uint32_t> slot_;
};

} // namespace

LodResult bakeLod(const std::vector<glm::vec3> &positions, const std::vector<uint32_t> &indices,
                  const LodOptions &o, Reporter &reporter, const std::vector<uint32_t> &group,
                  const std::vector<std::vector<glm::vec3>> &poses) {
  for (const auto &pose : poses)
    if (pose.size() != positions.size())
      throw Error("lod: a pose has another vertex count than the mesh");
  if (indices.size() % 3 != 0)
    throw Error("lod: the index count is not a multiple of 3");
  for (uint32_t i : indices)
    if (i >= positions.size())
      throw Error("lod: an index points past the vertices");
  LodResult r;
  r.inputTriangles = uint32_t(indices.size() / 3);
  lod::FanMesh m = lod::buildFanMesh(positions, indices, group);
  if (m.degenerate)
    reporter.warn("degenerate_triangles",
                  std::to_string(m.degenerate) + " zero-area triangles dropped from the LOD mesh");
  if (m.duplicate)
    reporter.warn("duplicate_triangles",
                  std::to_string(m.duplicate) + " duplicate triangles dropped from the LOD mesh");
  if (m.splitVertices || m.cutEdges)
    reporter.warn("non_manifold", std::to_string(m.cutEdges) +
                                      " edges with more than two faces (or wound both "
                                      "ways) cut open; " +
                                      std::to_string(m.splitVertices) + " vertices where " +
                                      "several fans meet split into one per fan (" +
                                      std::to_string(m.extraFans) +
                                      " added), each fan simplifying on its own");
  if (m.vertex.empty())
    throw Error("lod: the mesh has no triangle with an area");

  const size_t V = m.source.size(), F = m.vertex.size(), N = m.position.size();
  const std::vector<std::array<uint32_t, 3>> initialCorner = m.render;
  // One quadric per vertex per pose (the rest pose and each of `poses`): a collapse costs what it
  // moves the surface in every pose, each measured where the vertex is in that pose. The rest of
  // the bake (normals, legality) looks at the rest pose alone.
  lod::PoseQuadrics quadric(m.position, poses, m.inputOf);
  const std::vector<glm::dvec3> &rest = m.position;
  lod::FaceLists facesOf = [&] {
    std::vector<uint32_t> valence(N, 0);
    for (const auto &fv : m.vertex)
      for (uint32_t v : fv)
        ++valence[v];
    return lod::FaceLists(valence);
  }();
  std::vector<glm::dvec3> originalNormal(F);
  auto normalOf = [&](const std::array<uint32_t, 3> &f) { // in the rest pose
    const glm::dvec3 &a = rest[f[0]];
    return glm::cross(rest[f[1]] - a, rest[f[2]] - a);
  };
  for (uint32_t f = 0; f < F; ++f) {
    const auto &fv = m.vertex[f];
    originalNormal[f] = glm::normalize(normalOf(fv));
    for (uint32_t v : fv)
      facesOf.push(v, f);
    quadric.addFace(fv);
  }
  std::vector<uint8_t> alive(F, 1);
  auto corner = [&](uint32_t f, uint32_t v) -> uint32_t {
    const auto &fv = m.vertex[f];
    return fv[0] == v ? 0 : fv[1] == v ? 1 : 2;
  };
  auto has = [&](uint32_t f, uint32_t v) {
    const auto &fv = m.vertex[f];
    return fv[0] == v || fv[1] == v || fv[2] == v;
  };
  // The live faces holding both a and b (at most two: the mesh stays manifold).
  auto edgeFaces = [&](uint32_t a, uint32_t b, uint32_t out[2]) {
    uint32_t n = 0;
    for (uint32_t f : facesOf[a])
      if (alive[f] && has(f, b) && n < 2)
        out[n++] = f;
    return n;
  };
  // v's neighbours, each edge to them open or a seam or neither, from one pass over v's faces.
  auto ringOf = [&](uint32_t v, Ring &ring) {
    ring.clear();
    for (uint32_t f : facesOf[v]) {
      if (!alive[f])
        continue;
      const uint32_t self = m.render[f][corner(f, v)];
      for (uint32_t k = 0; k < 3; ++k) {
        const uint32_t w = m.vertex[f][k];
        if (w == v)
          continue;
        if (Neighbour *n = ring.find(w); !n)
          ring.add({w, 1, f, UINT32_MAX, self, m.render[f][k], false});
        else if (++n->faces == 2)
          n->second = f, n->special = n->renderSelf != self || n->renderOther != m.render[f][k];
      }
    }
    for (Neighbour &n : ring.around)
      n.special |= n.faces == 1;
  };
  // Boundaries and seams also hold their shape: each special edge adds, to both ends, a plane
  // through it, perpendicular to its face (PoseQuadrics::addBorder). Each vertex's ring says
  // which of its edges are special (edgeFaces for each edge took 6% of CesiumMan's bake); the
  // planes then go in face by face, each edge from its first face, so that every quadric sums
  // them in one order. open[f], special[f]: a bit for each of the face's open (special) edges,
  // from corner e to e + 1.
  std::vector<uint8_t> open(F, 0), special(F, 0);
  Ring ringA(N), ringB(N);
  for (uint32_t v = 0; v < N; ++v) {
    ringOf(v, ringA);
    for (const Neighbour &n : ringA.around) {
      if (!n.special)
        continue;
      const uint32_t f = n.first, cv = corner(f, v), cw = corner(f, n.v);
      const uint32_t e = cw == (cv + 1) % 3 ? cv : cw; // facesOf lists ascend: f is the first
      special[f] |= uint8_t(1u << e);
      open[f] |= uint8_t(n.faces == 1) << e;
    }
  }
  for (uint32_t f = 0; f < F; ++f)
    for (uint32_t e = 0; e < 3; ++e)
      if (special[f] >> e & 1)
        quadric.addBorder(m.vertex[f][e], m.vertex[f][(e + 1) % 3], m.vertex[f][(e + 2) % 3]);

  quadric.finish();
  const double cosLimit = std::cos(o.maxNormalDeviationDeg * 3.14159265358979323846 / 180);
  // Whether a may collapse into b; `ab` and `sides`: the edge's live faces (as edgeFaces finds
  // them), which the collapse then takes.
  auto legal = [&](uint32_t a, uint32_t b, uint32_t ab[2], uint32_t &sides) -> Block {
    ringOf(a, ringA);
    const Neighbour *edge = ringA.find(b);
    if (!edge)
      return Block::kNoEdge; // no longer an edge
    sides = std::min(edge->faces, 2u), ab[0] = edge->first, ab[1] = edge->second;
    // A seam or boundary vertex slides only along its line: exactly two special edges, and
    // this one of them.
    int specials = 0;
    bool along = false;
    for (const Neighbour &n : ringA.around)
      if (n.special) {
        ++specials;
        along |= n.v == b;
      }
    if (specials != 0 && !(specials == 2 && along))
      return Block::kSeam;
    ringOf(b, ringB); // only past the seam test: of Fox's 994 checks, 625 stop there
    // The link condition: the vertices next to both ends are exactly the faces' apexes (which
    // are always next to both: the count says whether there are others), so the mesh stays
    // manifold; an inner edge joining two boundary vertices would pinch it.
    uint32_t apex[2] = {UINT32_MAX, UINT32_MAX};
    for (uint32_t s = 0; s < sides; ++s)
      for (uint32_t w : m.vertex[ab[s]])
        if (w != a && w != b)
          apex[s] = w;
    uint32_t common = 0;
    for (const Neighbour &n : ringA.around)
      common += ringB.count(n.v) != 0;
    if (common != sides)
      return Block::kManifold;
    auto onBoundary = [](const Ring &ring) {
      for (const Neighbour &n : ring.around)
        if (n.faces == 1)
          return true;
      return false;
    };
    if (sides == 2 && onBoundary(ringA) && onBoundary(ringB))
      return Block::kManifold;
    for (uint32_t s = 0; s < sides; ++s) // a face with two open edges would leave a dangling one
      if (ringA.count(apex[s]) == 1 && ringB.count(apex[s]) == 1)
        return Block::kManifold;
    const glm::dvec3 target = rest[b];
    for (uint32_t f : facesOf[a]) {
      if (!alive[f] || has(f, b))
        continue; // this face disappears
      // A tetrahedron: the faces left would be one triangle twice. Stricter than that: a face of
      // a holds both apexes whenever a has valence 3, so such a vertex inside a surface never
      // goes; only where b also has a face on both apexes do the faces double. The exact test
      // moved lod_bench's animated error both ways (21 of its 60 levels better, 15 worse; issue
      // 17's notes), so it waits for a less tie-sensitive order.
      if (sides == 2 && has(f, apex[0]) && has(f, apex[1]))
        return Block::kManifold;
      std::array<uint32_t, 3> fv = m.vertex[f];
      const glm::dvec3 before = normalOf(fv);
      glm::dvec3 p[3];
      for (int k = 0; k < 3; ++k)
        p[k] = fv[size_t(k)] == a ? target : rest[fv[size_t(k)]];
      const glm::dvec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
      const double len = glm::length(n);
      if (len <= 1e-12 * glm::dot(target, target) + 1e-30)
        return Block::kNormal;
      if (glm::dot(n / len, originalNormal[f]) < cosLimit || glm::dot(n, before) <= 0)
        return Block::kNormal;
    }
    return Block::kNone;
  };
  // The Refusals slot of the collapse of a into b, an edge of the faces ab (legal()'s).
  auto slotOf = [&](uint32_t a, uint32_t b, const uint32_t ab[2],
                    uint32_t sides) -> lod::Refusals::Slot {
    for (uint32_t s = 0; s < sides; ++s)
      if (const uint32_t f = ab[s], e = corner(f, a); m.vertex[f][(e + 1) % 3] == b)
        return {3 * size_t(f) + e, false};               // the face winding a -> b
    return {3 * size_t(ab[0]) + corner(ab[0], b), true}; // an open edge's other way
  };
  lod::Refusals refusals(N, F);

  // A vertex's stamp moves on when it takes a collapse and when it goes: a candidate is stale
  // exactly where an end's stamp differs from the one it was pushed with.
  std::vector<uint32_t> stamp(N, 0);
  lod::CostQueue<Candidate> queue;
  queue.reserve(3 * F + 64); // the first pass's pushes on a closed mesh: no copies as it fills
  // A candidate goes in at its bound, and its cost is worked out only when the bound comes up,
  // if the candidate is still valid then: of the sample humanoid's 70,340 candidates, 65,060 were
  // stale when they came up, and their costs over 16 poses were most of the bake's arithmetic.
  const bool boundIsCost = quadric.boundIsCost();
  auto push = [&](uint32_t from, uint32_t to) {
    const double bound = quadric.bound(from, to);
    queue.push(quadric.key(from, to, bound),
               {float(bound), from, to, stamp[from] + stamp[to], boundIsCost, 0});
  };
  // Both ways of an edge as one candidate: the way that comes up first (in one bucket, the ring
  // vertex into the one kept, as when both went in and the last pushed popped first), which
  // queues the other way only where it comes up valid and is not taken; once it is taken, the
  // other way is stale. Half the pushes after each collapse: lod_bench's 1M grid 1.40 -> 1.17 s
  // and peak +352 -> +306 MB, the small models 2-7% (tests/bench/lod_speed.sh). The other way
  // now queues behind what its bucket took since, so ties fall otherwise: of lod_bench's 60
  // animated errors under 100%, 2 better, 3 worse (by under 4%), the rest the same.
  auto pushEdge = [&](uint32_t u, uint32_t w) {
    double bu = quadric.bound(u, w), bw = quadric.bound(w, u);
    double ku = quadric.key(u, w, bu), kw = quadric.key(w, u, bw);
    if (!queue.sooner(ku, kw))
      std::swap(u, w), bu = bw, ku = kw;
    queue.push(ku, {float(bu), u, w, stamp[u] + stamp[w], boundIsCost, 1});
  };

  // Removal record, in render vertices: who goes, into whom, at what cost; and for each face,
  // the render vertex whose removal deletes it.
  std::vector<uint32_t> removed, target(V, UINT32_MAX);
  removed.reserve(V); // each render vertex goes at most once
  std::vector<float> cost(V, 0.0f);
  std::vector<int64_t> killer(F, -1);
  size_t aliveFaces = F;
  const size_t floorFaces = size_t(std::ceil(o.floorFraction * double(F)));
  bool progress = true, first = true; // first: the first pass over the edges
  while (aliveFaces > floorFaces && progress) {
    // Costs change only around a collapse, but legality can change one ring further out: when
    // the queue runs dry, every remaining edge gets another chance until none is legal, but for
    // those whose refusal still stands. Each face pushes its edges as wound; an open edge is
    // pushed both ways.
    for (uint32_t f = 0; f < F; ++f) {
      if (!alive[f])
        continue;
      for (uint32_t e = 0; e < 3; ++e) {
        const uint32_t a = m.vertex[f][e], b = m.vertex[f][(e + 1) % 3];
        const size_t at = 3 * size_t(f) + e;
        uint32_t sides[2];
        if (!refusals.stands({at, false}, a, b))
          push(a, b);
        if ((first ? open[f] >> e & 1 : edgeFaces(a, b, sides) == 1) &&
            !refusals.stands({at, true}, b, a))
          push(b, a);
      }
    }
    progress = first = false;
    while (!queue.empty() && aliveFaces > floorFaces) {
      Candidate c = queue.pop();
      const uint32_t a = c.from, b = c.to;
      if (stamp[a] + stamp[b] != c.stamps)
        continue;
      const bool pair = c.pair;
      c.pair = 0;
      if (!c.exact) { // its cost, now; if that comes up later, it waits its turn there
        c.cost = float(quadric.cost(a, b)), c.exact = 1;
        if (queue.later(c.cost)) {
          queue.push(c.cost, c);
          if (pair)
            push(b, a);
          continue;
        }
      }
      uint32_t ab[2], sides;
      if (const Block why = legal(a, b, ab, sides); why != Block::kNone) {
        if (pair)
          push(b, a);
        if (why != Block::kNoEdge)
          refusals.refuse(slotOf(a, b, ab, sides), why);
        continue;
      }
      // Pair each render vertex of `a` with the render vertex of `b` on the same side.
      std::array<std::pair<uint32_t, uint32_t>, 2> pairs;
      size_t pairCount = 0;
      for (uint32_t s = 0; s < sides; ++s) {
        const uint32_t f = ab[s], ra = m.render[f][corner(f, a)], rb = m.render[f][corner(f, b)];
        if (pairCount == 0 || pairs[0].first != ra)
          pairs[pairCount++] = {ra, rb};
        killer[f] = ra;
        alive[f] = 0;
        --aliveFaces;
      }
      for (uint32_t f : facesOf[a]) {
        if (!alive[f])
          continue;
        const uint32_t k = corner(f, a), rv = m.render[f][k];
        size_t q = 0;
        while (q < pairCount && pairs[q].first != rv)
          ++q;
        if (q == pairCount) // cannot happen: legal() keeps seams to their lines
          throw Error("lod: internal error, a render vertex has no partner");
        m.vertex[f][k] = b;
        m.render[f][k] = pairs[q].second;
      }
      for (size_t q = 0; q < pairCount; ++q) {
        removed.push_back(pairs[q].first);
        target[pairs[q].first] = pairs[q].second;
        cost[pairs[q].first] = c.cost;
      }
      quadric.merge(b, a);
      facesOf.handOn(a, b, [&](uint32_t f) { return alive[f] != 0; });
      ++stamp[a], ++stamp[b];
      progress = true;
      ringOf(b, ringB);
      refusals.collapsed();
      refusals.changed(b);
      for (const Neighbour &n : ringB.around) {
        refusals.changed(n.v);
        pushEdge(b, n.v);
      }
    }
    queue.clear();
  }

  if (aliveFaces > floorFaces) { // say why: what stops each edge that is left, both ways
    // As refused in the last pass, which collapsed nothing: each refusal stands. ab: the edge's
    // faces, which slotOf takes in either order.
    auto reason = [&](uint32_t a, uint32_t b, const uint32_t ab[2], uint32_t sides) {
      const lod::Refusals::Slot slot = slotOf(a, b, ab, sides);
      uint32_t faces[2], n;
      return refusals.stands(slot, a, b) ? refusals.why(slot) : legal(a, b, faces, n);
    };
    size_t seam = 0, manifold = 0, normal = 0, edges = 0;
    for (uint32_t f = 0; f < F; ++f)
      for (uint32_t e = 0; alive[f] && e < 3; ++e) {
        const uint32_t a = m.vertex[f][e], b = m.vertex[f][(e + 1) % 3];
        uint32_t faces[2];
        const uint32_t sides = edgeFaces(a, b, faces);
        if (sides == 2 && faces[0] != f)
          continue; // each edge once
        ++edges;
        const Block ab = reason(a, b, faces, sides), ba = reason(b, a, faces, sides);
        seam += ab == Block::kSeam && ba == Block::kSeam;
        normal += (ab == Block::kNormal || ba == Block::kNormal) && ab != Block::kManifold &&
                  ba != Block::kManifold;
        manifold += ab == Block::kManifold || ba == Block::kManifold;
      }
    auto pct = [](double x) { return std::to_string(int(std::lround(100 * x))) + "%"; };
    reporter.warn("lod_floor_not_reached",
                  "the LOD stops at " + std::to_string(aliveFaces) + " of " + std::to_string(F) +
                      " triangles (" + pct(double(aliveFaces) / double(F)) + ", the floor is " +
                      pct(o.floorFraction) + "): no legal collapse is left. Of its " +
                      std::to_string(edges) + " edges, " + std::to_string(seam) +
                      " join two seam or boundary corners (UV seams, hard edges, open borders: "
                      "each moves only along its line), " +
                      std::to_string(manifold) +
                      " would make the mesh non-manifold (a piece down to its last faces), " +
                      std::to_string(normal) + " would turn a face more than " +
                      std::to_string(int(o.maxNormalDeviationDeg)) + " degrees");
  }

  // Numbering: vertices never removed first (input order), then the removed ones, last removed
  // first; render vertices no face uses (isolated) go last, into vertex 0.
  std::vector<uint8_t> used(V, 0);
  for (const auto &c : m.render)
    for (uint32_t rv : c)
      used[rv] = 1;
  for (uint32_t t = 0; t < r.inputTriangles; ++t)
    for (int k = 0; k < 3; ++k)
      used[indices[3 * t + size_t(k)]] |= 2; // referenced by the input at all
  std::vector<uint32_t> newIndex(V, UINT32_MAX);
  for (uint32_t v = 0; v < V; ++v)
    if (used[v] & 1 && target[v] == UINT32_MAX)
      newIndex[v] = uint32_t(r.order.size()), r.order.push_back(m.source[v]);
  r.floorVertices = uint32_t(r.order.size());
  for (auto it = removed.rbegin(); it != removed.rend(); ++it)
    newIndex[*it] = uint32_t(r.order.size()), r.order.push_back(m.source[*it]);
  size_t isolated = 0;
  for (uint32_t v = 0; v < V; ++v)
    if (newIndex[v] == UINT32_MAX) {
      newIndex[v] = uint32_t(r.order.size()), r.order.push_back(m.source[v]);
      isolated += !(used[v] & 2);
    }
  if (isolated)
    reporter.warn("isolated_vertices",
                  std::to_string(isolated) + " vertices no triangle uses: last in the LOD order");
  r.collapse.resize(r.order.size());
  r.error.assign(r.order.size(), 0.0f);
  for (uint32_t v = 0; v < V; ++v) {
    uint32_t k = newIndex[v];
    r.collapse[k] = target[v] != UINT32_MAX ? newIndex[target[v]] : (k < r.floorVertices ? k : 0);
    r.error[k] = cost[v];
  }

  // Triangles: those that survive to the floor first, then the rest, last deleted first (the
  // lower its killer's new index, the later a triangle goes).
  auto death = [&](uint32_t f) {
    return killer[f] < 0 ? uint32_t(UINT32_MAX) : newIndex[size_t(killer[f])];
  };
  auto rank = [&](uint32_t f) { return killer[f] < 0 ? size_t(0) : size_t(death(f)) + 1; };
  std::vector<uint32_t> faces(F), start(V + 2, 0); // sorted by rank, stable: a counting sort
  for (uint32_t f = 0; f < F; ++f)
    ++start[rank(f) + 1];
  for (size_t k = 1; k < start.size(); ++k)
    start[k] += start[k - 1];
  for (uint32_t f = 0; f < F; ++f)
    faces[start[rank(f)]++] = f;
  // A face is alive at v vertices while its killer (new index d) is < v.
  r.triangleCount.assign(r.order.size() + 1, 0);
  for (uint32_t f : faces) {
    for (int k = 0; k < 3; ++k) // the input triangle's corners and winding
      r.indices.push_back(newIndex[initialCorner[f][size_t(k)]]);
    uint32_t d = death(f);
    ++r.triangleCount[d == UINT32_MAX ? 0 : d + 1];
    r.source.push_back(m.inputTriangle[f]);
    r.killedBy.push_back(d);
  }
  for (size_t v = 1; v < r.triangleCount.size(); ++v)
    r.triangleCount[v] += r.triangleCount[v - 1];
  return r;
}

LodTriangles lodTriangles(const SkinnedMesh &in) {
  const std::vector<uint32_t> partOf = triangleParts(in);
  const uint32_t triangles = uint32_t(in.indices.size() / 3);
  LodTriangles lt;
  lt.group.assign(in.positions.size(), 0);
  std::map<std::array<uint32_t, 3>, uint32_t> first; // a triangle's vertices -> distinct index
  for (uint32_t t = 0; t < triangles; ++t) {
    std::array<uint32_t, 3> v = {in.indices[3 * t], in.indices[3 * t + 1], in.indices[3 * t + 2]};
    std::rotate(v.begin(), std::min_element(v.begin(), v.end()), v.end()); // keeps the winding
    const auto it = first.find(v);
    // A repeat within one sub-mesh is a duplicate face: bakeLod drops it and says so.
    if (it != first.end() && partOf[lt.inputsOf[it->second][0]] != partOf[t]) {
      lt.inputsOf[it->second].push_back(t);
      continue;
    }
    first.emplace(v, uint32_t(lt.inputsOf.size()));
    lt.inputsOf.push_back({t});
    lt.indices.insert(lt.indices.end(), &in.indices[3 * t], &in.indices[3 * t] + 3);
    for (uint32_t k : v)
      lt.group[k] = partOf[t];
  }
  // Vertices weld only within a sub-mesh and a skin binding: two at one rest position bound to
  // other joints or weights part when the character moves (one mesh under several skins).
  std::map<std::vector<uint32_t>, uint32_t> groupOf;
  for (size_t k = 0; k < lt.group.size(); ++k) {
    std::vector<uint32_t> key{lt.group[k]};
    for (int i = 0; i < 4; ++i) {
      key.push_back(in.weights[k][i] > 0 ? in.joints[k][size_t(i)] : 0);
      lod::putBits(key, in.weights[k][i]);
    }
    lt.group[k] = groupOf.try_emplace(std::move(key), uint32_t(groupOf.size())).first->second;
  }
  return lt;
}

std::vector<uint32_t> triangleParts(const SkinnedMesh &m) {
  std::vector<uint32_t> part(m.indices.size() / 3, 0);
  for (uint32_t p = 0; p < m.parts.size(); ++p)
    for (uint32_t t = m.parts[p].firstIndex / 3;
         t < (m.parts[p].firstIndex + m.parts[p].indexCount) / 3 && t < part.size(); ++t)
      part[t] = p;
  return part;
}

std::vector<std::vector<glm::vec3>> samplePoses(const Character &c, uint32_t count) {
  std::vector<std::vector<glm::vec3>> poses;
  if (c.clips.empty())
    return poses;
  const uint32_t perClip = uint32_t((count + c.clips.size() - 1) / c.clips.size());
  for (uint32_t i = 0; i < count; ++i) { // round robin over the clips, mid-interval times
    const AnimationClip &clip = c.clips[i % c.clips.size()];
    double t = clip.start + (clip.end - clip.start) * (double(i / c.clips.size()) + 0.5) / perClip;
    auto skinned = posedPositions(c, &clip, t);
    poses.emplace_back(skinned.begin(), skinned.end());
  }
  return poses;
}

void LodOptions::validate() const {
  if (!(floorFraction >= 0 && floorFraction <= 1))
    throw Error("floor: must be in [0, 1]");
  if (poses > 1024)
    throw Error("poses: must be an integer in [0, 1024]");
  if (!(maxNormalDeviationDeg > 0 && maxNormalDeviationDeg <= 180))
    throw Error("max normal deviation: must be in (0, 180] degrees");
}

namespace {

// Each repeat goes with its first: the same new indices, the same vertex removal deleting it, so
// an outfit's copy simplifies exactly as the part it copies (see lodTriangles). Returns bakeLod's
// result with the repeats listed after their first (r.source: input triangles).
LodResult bakeWithRepeats(const Character &c, const LodOptions &o, Reporter &reporter) {
  const SkinnedMesh &in = c.mesh;
  const uint32_t triangles = uint32_t(in.indices.size() / 3);
  const LodTriangles lt = lodTriangles(in);
  const auto &inputsOf = lt.inputsOf;
  // The rest pose as drawn, not the mesh's own coordinates: those are in another unit where the
  // armature carries a scale (a trooper modelled in cm under a 0.01 armature: its bind-pose cost
  // outweighed every other pose's 10^7 times), and a rigid part's sit in its node's frame.
  const std::vector<glm::dvec3> rest = posedPositions(c, nullptr, 0);
  LodResult r = bakeLod(std::vector<glm::vec3>(rest.begin(), rest.end()), lt.indices, o, reporter,
                        lt.group, samplePoses(c, o.poses));
  const std::vector<uint32_t> source = std::move(r.source), killedBy = std::move(r.killedBy),
                              indices = std::move(r.indices);
  r.source.clear(), r.killedBy.clear(), r.indices.clear();
  std::vector<uint32_t> listed(source.size() + 1, 0); // input triangles of the first t kept
  for (size_t t = 0; t < source.size(); ++t) {
    for (uint32_t input : inputsOf[source[t]]) {
      r.source.push_back(input);
      r.killedBy.push_back(killedBy[t]);
      r.indices.insert(r.indices.end(), &indices[3 * t], &indices[3 * t] + 3);
    }
    listed[t + 1] = uint32_t(r.source.size());
  }
  for (uint32_t &count : r.triangleCount)
    count = listed[count];
  r.inputTriangles = triangles;
  return r;
}

} // namespace

pack::Lod applyLod(Character &c, const LodOptions &o, Reporter &reporter, LodResult *details,
                   const std::vector<uint32_t> &keep) {
  o.validate();
  std::vector<uint32_t> newOf(c.mesh.positions.size(), UINT32_MAX), keepNow;
  const std::vector<uint32_t> copyWas = weldExactCopies(c.mesh, reporter, keep);
  for (uint32_t k = 0; k < copyWas.size(); ++k)
    newOf[copyWas[k]] = k;
  for (uint32_t v : keep) // renumbered past the copies' weld, which keeps them all
    if (v < newOf.size() && newOf[v] != UINT32_MAX)
      keepNow.push_back(newOf[v]);
  std::vector<uint32_t> was = weldFlatShading(c.mesh, reporter, 1, keepNow);
  for (uint32_t &v : was)
    v = copyWas[v];
  SkinnedMesh &in = c.mesh;
  const std::vector<uint32_t> partOf = triangleParts(in);
  reporter.step("LOD: collapse order of " + std::to_string(in.indices.size() / 3) + " triangles");
  LodResult r = bakeWithRepeats(c, o, reporter);
  SkinnedMesh out;
  out.morphDefaults = in.morphDefaults;
  for (const auto &target : in.morphs)
    out.morphs.push_back({target.name, {}, {}});
  for (uint32_t v : r.order) {
    for (size_t t = 0; t < in.morphs.size(); ++t) {
      out.morphs[t].positions.push_back(in.morphs[t].positions[v]);
      out.morphs[t].normals.push_back(in.morphs[t].normals[v]);
    }
    out.positions.push_back(in.positions[v]);
    out.normals.push_back(in.normals[v]);
    if (!in.uvs.empty())
      out.uvs.push_back(in.uvs[v]);
    out.joints.push_back(in.joints[v]);
    out.weights.push_back(in.weights[v]);
    if (!in.sources.empty())
      out.sources.push_back(in.sources[v]);
  }
  // Each part keeps its triangles, in the LOD order; its counts follow from when each goes.
  const uint32_t n = uint32_t(r.order.size());
  pack::Lod lod;
  lod.floorVertices = r.floorVertices;
  lod.collapse = r.collapse;
  lod.error = r.error;
  lod.triangleCounts.assign(in.parts.size() * (size_t(n) + 1), 0);
  for (uint32_t p = 0; p < in.parts.size(); ++p) {
    SkinnedMesh::Part part = in.parts[p]; // keeps its material
    part.firstIndex = uint32_t(out.indices.size());
    uint32_t *counts = &lod.triangleCounts[size_t(p) * (n + 1)];
    for (size_t t = 0; t < r.source.size(); ++t) {
      if (partOf[r.source[t]] != p)
        continue;
      out.indices.insert(out.indices.end(), &r.indices[3 * t], &r.indices[3 * t] + 3);
      ++counts[r.killedBy[t] == UINT32_MAX ? 0 : r.killedBy[t] + 1];
    }
    for (uint32_t v = 1; v <= n; ++v)
      counts[v] += counts[v - 1];
    part.indexCount = uint32_t(out.indices.size()) - part.firstIndex;
    out.parts.push_back(part);
  }
  c.mesh = std::move(out);
  if (details) {
    for (uint32_t &v : r.order) // the caller's vertices, before the welds
      v = was[v];
    *details = std::move(r);
  }
  return lod;
}

} // namespace crowd
