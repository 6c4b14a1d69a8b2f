#include "fan_mesh.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <numeric>

namespace crowd::lod {
namespace {

struct WeldKey {
  uint32_t bits[4]; // group, then x, y, z as bit patterns (-0 made +0 first)
  bool operator==(const WeldKey &o) const { return std::memcmp(bits, o.bits, sizeof bits) == 0; }
};
struct WeldHash {
  size_t operator()(const WeldKey &k) const {
    uint64_t h = 1469598103934665603ull;
    for (uint32_t b : k.bits)
      h = (h ^ b) * 1099511628211ull;
    return size_t(h ^ (h >> 29));
  }
};

uint32_t bitsOf(float f) {
  f += 0.0f; // -0 -> +0: both weld together, as they compare equal
  uint32_t b;
  std::memcpy(&b, &f, sizeof b);
  return b;
}

// Sorted as std::sort would, by way of a counting sort on each item's first key (a vertex id
// under `keys`) and a sort of each small group: half the time of one sort of the whole array.
template <class T, class First> void sortGrouped(std::vector<T> &items, size_t keys, First first) {
  std::vector<uint32_t> start(keys + 1, 0);
  for (const T &x : items)
    ++start[first(x) + 1];
  for (size_t k = 0; k < keys; ++k)
    start[k + 1] += start[k];
  std::vector<T> grouped(items.size());
  std::vector<uint32_t> at(start.begin(), start.end() - 1);
  for (const T &x : items)
    grouped[at[first(x)]++] = x;
  for (size_t k = 0; k < keys; ++k)
    std::sort(grouped.begin() + start[k], grouped.begin() + start[k + 1]);
  items.swap(grouped);
}

uint32_t findRoot(std::vector<uint32_t> &parent, uint32_t x) {
  while (parent[x] != x)
    x = parent[x] = parent[parent[x]];
  return x;
}

// Every input vertex's welded id, by position within its group, numbered in input order: an
// open-addressed table of welded ids, keyed by their first input vertex's key.
struct Welded {
  std::vector<uint32_t> id;         // per input vertex
  std::vector<glm::dvec3> position; // per welded id
};
Welded weldVertices(const std::vector<glm::vec3> &positions, const std::vector<uint32_t> &group) {
  Welded w;
  w.id.resize(positions.size());
  std::vector<WeldKey> weldedKey;
  size_t slots = 16;
  while (slots < 2 * positions.size())
    slots *= 2;
  std::vector<uint32_t> table(slots, UINT32_MAX);
  for (size_t v = 0; v < positions.size(); ++v) {
    const glm::vec3 &p = positions[v];
    const WeldKey key{{group.empty() ? 0u : group[v], bitsOf(p.x), bitsOf(p.y), bitsOf(p.z)}};
    size_t slot = WeldHash()(key) & (slots - 1);
    while (table[slot] != UINT32_MAX && !(weldedKey[table[slot]] == key))
      slot = (slot + 1) & (slots - 1);
    if (table[slot] == UINT32_MAX) {
      table[slot] = uint32_t(w.position.size());
      w.position.push_back(glm::dvec3(p));
      weldedKey.push_back(key);
    }
    w.id[v] = table[slot];
  }
  return w;
}

// The triangles with an area, the first of each set over the same welded vertices kept: their
// input triangles into `m` (with the counts of those dropped), their welded corners returned.
std::vector<std::array<uint32_t, 3>> keepTriangles(const std::vector<uint32_t> &indices,
                                                   const Welded &welded, FanMesh &m) {
  const uint32_t T = uint32_t(indices.size() / 3);
  auto corners = [&](uint32_t t) {
    return std::array<uint32_t, 3>{welded.id[indices[3 * t]], welded.id[indices[3 * t + 1]],
                                   welded.id[indices[3 * t + 2]]};
  };
  std::vector<std::pair<std::array<uint32_t, 3>, uint32_t>> keyed; // sorted welded ids, triangle
  keyed.reserve(T);
  for (uint32_t t = 0; t < T; ++t) {
    std::array<uint32_t, 3> w = corners(t);
    const glm::dvec3 a = welded.position[w[0]], b = welded.position[w[1]],
                     c = welded.position[w[2]];
    if (w[0] == w[1] || w[1] == w[2] || w[0] == w[2] ||
        glm::length(glm::cross(b - a, c - a)) == 0) {
      ++m.degenerate;
      continue;
    }
    std::sort(w.begin(), w.end());
    keyed.push_back({w, t});
  }
  sortGrouped(keyed, welded.position.size(), [](const auto &k) { return k.first[0]; });
  std::vector<uint8_t> keep(T, 0);
  for (size_t k = 0; k < keyed.size(); ++k) {
    if (k > 0 && keyed[k].first == keyed[k - 1].first)
      ++m.duplicate;
    else
      keep[keyed[k].second] = 1;
  }
  std::vector<std::array<uint32_t, 3>> weldedFace;
  for (uint32_t t = 0; t < T; ++t)
    if (keep[t]) {
      m.inputTriangle.push_back(t);
      weldedFace.push_back(corners(t));
    }
  return weldedFace;
}

// Corner c of face f is 3f + c.
uint32_t nextCorner(uint32_t corner) { return corner - corner % 3 + (corner % 3 + 1) % 3; }

// Each edge's two sides paired: exactly two faces, wound opposite ways, join their corners at
// each end into one fan (a union-find over corners, returned as parents). Other edges stay open;
// those with more than two sides are counted as cut.
std::vector<uint32_t> pairEdges(const std::vector<std::array<uint32_t, 3>> &weldedFace,
                                size_t weldedCount, FanMesh &m) {
  const uint32_t F = uint32_t(weldedFace.size());
  struct EdgeEntry {
    uint32_t lo, hi, corner; // corner f*3+e: the edge from corner e to corner e+1 of face f
    bool operator<(const EdgeEntry &o) const {
      return lo != o.lo ? lo < o.lo : hi != o.hi ? hi < o.hi : corner < o.corner;
    }
  };
  std::vector<EdgeEntry> edges;
  edges.reserve(size_t(F) * 3);
  for (uint32_t f = 0; f < F; ++f)
    for (uint32_t e = 0; e < 3; ++e) {
      uint32_t a = weldedFace[f][e], b = weldedFace[f][(e + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), 3 * f + e});
    }
  sortGrouped(edges, weldedCount, [](const EdgeEntry &e) { return e.lo; });
  std::vector<uint32_t> parent(size_t(F) * 3);
  std::iota(parent.begin(), parent.end(), 0u);
  auto unite = [&](uint32_t x, uint32_t y) {
    x = findRoot(parent, x), y = findRoot(parent, y);
    if (x != y)
      parent[std::max(x, y)] = std::min(x, y);
  };
  auto from = [&](uint32_t corner) { return weldedFace[corner / 3][corner % 3]; };
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi)
      ++j;
    if (j - i == 2 && from(edges[i].corner) == from(nextCorner(edges[i + 1].corner))) {
      // Side one runs A -> B (corners c, next(c)); side two B -> A (corners d, next(d)).
      const uint32_t c = edges[i].corner, d = edges[i + 1].corner;
      unite(c, nextCorner(d));
      unite(nextCorner(c), d);
    } else if (j - i > 1) {
      ++m.cutEdges;
    }
    i = j;
  }
  return parent;
}

// One topological vertex per fan (the corners joined across paired edges), numbered as their
// first corner comes: m.vertex, m.position and m.inputOf, and the counts of split vertices.
void numberFans(const std::vector<std::array<uint32_t, 3>> &weldedFace, const Welded &welded,
                const std::vector<uint32_t> &indices, std::vector<uint32_t> &parent, FanMesh &m) {
  const uint32_t F = uint32_t(weldedFace.size());
  auto from = [&](uint32_t corner) { return weldedFace[corner / 3][corner % 3]; };
  std::vector<uint32_t> fanOf(size_t(F) * 3, UINT32_MAX), fansAt(welded.position.size(), 0);
  m.vertex.resize(F);
  for (uint32_t c = 0; c < 3 * F; ++c) {
    const uint32_t root = findRoot(parent, c);
    if (fanOf[root] == UINT32_MAX) {
      fanOf[root] = uint32_t(m.position.size());
      m.position.push_back(welded.position[from(c)]);
      m.inputOf.push_back(indices[3 * m.inputTriangle[c / 3] + c % 3]);
      if (++fansAt[from(c)] == 2)
        ++m.splitVertices;
    }
    m.vertex[c / 3][c % 3] = fanOf[root];
  }
  for (uint32_t n : fansAt)
    m.extraFans += n > 1 ? n - 1 : 0;
}

// Render vertices: the input vertices, copied where a second fan uses one (m.source, m.render).
void numberRenderVertices(size_t inputVertices, const std::vector<uint32_t> &indices, FanMesh &m) {
  const uint32_t F = uint32_t(m.vertex.size());
  m.source.resize(inputVertices);
  std::iota(m.source.begin(), m.source.end(), 0u);
  std::vector<uint32_t> claimedBy(inputVertices, UINT32_MAX);
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> copyOf; // (input vertex, fan) -> copy
  m.render.resize(F);
  for (uint32_t c = 0; c < 3 * F; ++c) {
    const uint32_t in = indices[3 * m.inputTriangle[c / 3] + c % 3], fan = m.vertex[c / 3][c % 3];
    uint32_t r = in;
    if (claimedBy[in] == UINT32_MAX) {
      claimedBy[in] = fan;
    } else if (claimedBy[in] != fan) {
      auto [it, fresh] = copyOf.try_emplace({in, fan}, uint32_t(m.source.size()));
      if (fresh)
        m.source.push_back(in);
      r = it->second;
    }
    m.render[c / 3][c % 3] = r;
  }
}

} // namespace

FanMesh buildFanMesh(const std::vector<glm::vec3> &positions, const std::vector<uint32_t> &indices,
                     const std::vector<uint32_t> &group) {
  FanMesh m;
  const Welded welded = weldVertices(positions, group);
  const auto weldedFace = keepTriangles(indices, welded, m);
  std::vector<uint32_t> parent = pairEdges(weldedFace, welded.position.size(), m);
  numberFans(weldedFace, welded, indices, parent, m);
  numberRenderVertices(positions.size(), indices, m);
  return m;
}

} // namespace crowd::lod
