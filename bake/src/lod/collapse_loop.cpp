#include "collapse_loop.h"

#include <algorithm>

#include "cost_queue.h"
#include "crowd/formats/error.h"

namespace crowd::lod {
namespace {

// A collapse of `from` into `to`, valid while neither vertex has changed since: stamps never go
// down, so their sum is the one it was pushed with exactly where neither moved on. Its cost, or
// until `exact` a lower bound of it (PoseQuadrics::bound). 20 bytes with the queue's link.
struct Candidate {
  float cost; // as the pack stores it; the queue's buckets hold fewer bits
  uint32_t from, to;
  uint32_t stamps : 30;         // each stamp <= the collapses < 2^29 (Refusals): the sum fits
  uint32_t exact : 1, pair : 1; // pair: the other way (to -> from) is not queued yet
};

// The candidates and each vertex's stamp, which moves on when it takes a collapse and when it
// goes: a candidate is stale exactly where an end's stamp differs from the one it was pushed
// with. A candidate goes in at its bound, and its cost is worked out only when the bound comes
// up, if the candidate is still valid then: most are stale by then.
class Candidates {
public:
  Candidates(const PoseQuadrics &quadric, size_t vertices, size_t faces)
      : quadric_(quadric), stamp_(vertices, 0), boundIsCost_(quadric.boundIsCost()) {
    queue_.reserve(3 * faces + 64); // the first pass's pushes on a closed mesh
  }
  void push(uint32_t from, uint32_t to) {
    const double bound = quadric_.bound(from, to);
    queue_.push(quadric_.key(from, to, bound),
                {float(bound), from, to, stamp_[from] + stamp_[to], boundIsCost_, 0});
  }
  // Both ways of an edge as one candidate: the way that comes up first (in one bucket, the ring
  // vertex into the one kept, as when both went in and the last pushed popped first), which
  // queues the other way only where it comes up valid and is not taken; once it is taken, the
  // other way is stale. Half the pushes after each collapse.
  void pushEdge(uint32_t u, uint32_t w) {
    double bu = quadric_.bound(u, w), bw = quadric_.bound(w, u);
    double ku = quadric_.key(u, w, bu), kw = quadric_.key(w, u, bw);
    if (!queue_.sooner(ku, kw))
      std::swap(u, w), bu = bw, ku = kw;
    queue_.push(ku, {float(bu), u, w, stamp_[u] + stamp_[w], boundIsCost_, 1});
  }
  // The next valid candidate at its exact cost, the other way of a pair queued where it goes
  // back for its cost; false when none is left.
  bool pop(Candidate &c) {
    while (!queue_.empty()) {
      c = queue_.pop();
      if (stamp_[c.from] + stamp_[c.to] != c.stamps)
        continue;
      if (c.exact)
        return true;
      const bool pair = c.pair;
      c.pair = 0, c.cost = float(quadric_.cost(c.from, c.to)), c.exact = 1;
      if (!queue_.later(c.cost)) {
        c.pair = pair;
        return true;
      }
      queue_.push(c.cost, c); // that comes up later: it waits its turn there
      if (pair)
        push(c.to, c.from);
    }
    return false;
  }
  void collapsed(uint32_t a, uint32_t b) { ++stamp_[a], ++stamp_[b]; }
  void clear() { queue_.clear(); }

private:
  const PoseQuadrics &quadric_;
  CostQueue<Candidate> queue_;
  std::vector<uint32_t> stamp_;
  bool boundIsCost_;
};

// Every live edge onto the queue, but those whose refusal still stands: each face pushes its
// edges as wound; an open edge is pushed both ways (`first`: the first pass, whose open edges
// the mesh marked).
void queueEveryEdge(const CollapseMesh &mesh, const Refusals &refusals, bool first,
                    Candidates &queue) {
  for (uint32_t f = 0; f < mesh.faces(); ++f) {
    if (!mesh.alive[f])
      continue;
    for (uint32_t e = 0; e < 3; ++e) {
      const uint32_t a = mesh.fan.vertex[f][e], b = mesh.fan.vertex[f][(e + 1) % 3];
      const size_t at = 3 * size_t(f) + e;
      if (!refusals.stands({at, false}, a, b))
        queue.push(a, b);
      if ((first ? mesh.open[f] >> e & 1 : mesh.edgeFaces(a, b).sides == 1) &&
          !refusals.stands({at, true}, b, a))
        queue.push(b, a);
    }
  }
}

// a goes into b: the edge's faces die, a's other faces take b in its place, each render vertex
// of a going into the render vertex of b on the same side, or where a hard edge closes into the
// one `closing` names (CollapseRules), and the quadrics and face lists follow.
void collapse(CollapseMesh &mesh, uint32_t a, uint32_t b, const EdgeFaces &edge,
              const std::vector<std::pair<uint32_t, uint32_t>> &closing, float cost,
              Removals &out) {
  std::array<std::pair<uint32_t, uint32_t>, 2> pairs;
  size_t pairCount = 0;
  for (uint32_t s = 0; s < edge.sides; ++s) {
    const uint32_t f = edge.face[s];
    const uint32_t ra = mesh.fan.render[f][mesh.corner(f, a)];
    const uint32_t rb = mesh.fan.render[f][mesh.corner(f, b)];
    if (pairCount == 0 || pairs[0].first != ra)
      pairs[pairCount++] = {ra, rb};
    out.killer[f] = ra;
    mesh.alive[f] = 0;
    --mesh.aliveFaces;
  }
  auto partner = [&](uint32_t rv) {
    for (size_t q = 0; q < pairCount; ++q)
      if (pairs[q].first == rv)
        return pairs[q].second;
    for (const auto &[ra, rb] : closing)
      if (ra == rv)
        return rb;
    // Cannot happen: the rules keep seams to their lines or close them.
    throw Error("lod: internal error, a render vertex has no partner");
  };
  for (uint32_t f : mesh.facesOf[a]) {
    if (!mesh.alive[f])
      continue;
    const uint32_t k = mesh.corner(f, a);
    mesh.fan.render[f][k] = partner(mesh.fan.render[f][k]);
    mesh.fan.vertex[f][k] = b;
  }
  auto removed = [&](uint32_t ra, uint32_t rb) {
    out.removed.push_back(ra);
    out.target[ra] = rb;
    out.cost[ra] = cost;
  };
  for (size_t q = 0; q < pairCount; ++q) {
    if (mesh.shading.active())
      mesh.shading.carried(pairs[q].first, pairs[q].second);
    removed(pairs[q].first, pairs[q].second);
  }
  for (const auto &[ra, rb] : closing) {
    out.colour[ra] = float(mesh.shading.closed(ra, rb));
    removed(ra, rb);
  }
  mesh.quadric.merge(b, a);
  mesh.facesOf.handOn(a, b, [&](uint32_t f) { return mesh.alive[f] != 0; });
}

} // namespace

// Costs change only around a collapse, but legality can change one ring further out: when the
// queue runs dry, every remaining edge gets another chance until none is legal.
Removals collapseToFloor(CollapseMesh &mesh, CollapseRules &rules, Refusals &refusals,
                         size_t floorFaces) {
  const size_t V = mesh.fan.source.size();
  Removals out;
  out.removed.reserve(V); // each render vertex goes at most once
  out.target.assign(V, UINT32_MAX);
  out.cost.assign(V, 0.0f);
  out.colour.assign(V, 0.0f);
  out.killer.assign(mesh.faces(), -1);
  Candidates queue(mesh.quadric, mesh.vertices(), mesh.faces());
  bool progress = true, first = true;
  while (mesh.aliveFaces > floorFaces && progress) {
    queueEveryEdge(mesh, refusals, first, queue);
    progress = first = false;
    Candidate c;
    while (mesh.aliveFaces > floorFaces && queue.pop(c)) {
      const uint32_t a = c.from, b = c.to;
      EdgeFaces edge;
      if (const Block why = rules.check(a, b, edge); why != Block::kNone) {
        if (c.pair)
          queue.push(b, a);
        if (why != Block::kNoEdge)
          refusals.refuse(rules.slotOf(a, b, edge), why);
        continue;
      }
      collapse(mesh, a, b, edge, rules.closing, c.cost, out);
      queue.collapsed(a, b);
      progress = true;
      mesh.ringOf(b, rules.ringB);
      refusals.collapsed();
      refusals.changed(b);
      for (const Neighbour &n : rules.ringB.around) {
        refusals.changed(n.v);
        queue.pushEdge(b, n.v);
      }
    }
    queue.clear();
  }
  return out;
}

} // namespace crowd::lod
