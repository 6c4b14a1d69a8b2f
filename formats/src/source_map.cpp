// The vertex source map (chunk SRCV): runs of source vertices and, unless the mesh keeps import
// order, one ordinal per mesh vertex.
#include <algorithm>

#include "crowd/formats/bytes.h"
#include "crowd/formats/chunks.h"
#include "crowd/formats/limits.h"

namespace crowd::pack {

namespace {

bool samePrimitive(const VertexSource &a, const VertexSource &b) {
  return a.file == b.file && a.node == b.node && a.mesh == b.mesh && a.primitive == b.primitive;
}

// Runs over `sources` in their order: each extends while the next vertex follows on.
std::vector<SourceMap::Run> runsOf(const std::vector<VertexSource> &sources) {
  std::vector<SourceMap::Run> runs;
  for (const auto &s : sources) {
    if (!runs.empty()) {
      auto &last = runs.back();
      if (samePrimitive(last.first, s) && int64_t(last.first.vertex) + last.count == s.vertex) {
        ++last.count;
        continue;
      }
    }
    runs.push_back({s, 1});
  }
  return runs;
}

} // namespace

SourceMap SourceMap::of(const std::vector<VertexSource> &perVertex) {
  SourceMap m;
  const bool made = std::any_of(perVertex.begin(), perVertex.end(),
                                [](const VertexSource &s) { return s.vertex < 0; });
  if (!made) { // import order: the runs alone say it, when that is the smaller
    m.runs = runsOf(perVertex);
    if (m.runs.size() * sizeof(Run) <= perVertex.size() * sizeof(uint32_t))
      return m;
  }
  std::vector<VertexSource> sorted;
  for (const auto &s : perVertex)
    if (s.vertex >= 0)
      sorted.push_back(s);
  std::sort(sorted.begin(), sorted.end());
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  m.runs = runsOf(sorted);
  for (const auto &s : perVertex)
    m.ordinals.push_back(s.vertex < 0 ? kMade
                                      : uint32_t(std::lower_bound(sorted.begin(), sorted.end(), s) -
                                                 sorted.begin()));
  return m;
}

uint64_t SourceMap::runVertices() const {
  uint64_t n = 0;
  for (const auto &r : runs)
    n += r.count;
  return n;
}

std::vector<VertexSource> SourceMap::expand() const {
  std::vector<VertexSource> all;
  for (const auto &r : runs)
    for (uint32_t k = 0; k < r.count; ++k) {
      all.push_back(r.first);
      all.back().vertex += int32_t(k);
    }
  if (ordinals.empty())
    return all;
  std::vector<VertexSource> out;
  out.reserve(ordinals.size());
  for (uint32_t o : ordinals)
    out.push_back(o == kMade ? VertexSource{} : all[o]);
  return out;
}

std::vector<uint8_t> encode(const SourceMap &m) {
  ByteWriter w;
  std::vector<int32_t> runs;
  for (const auto &r : m.runs)
    for (int32_t v : {r.first.file, r.first.node, r.first.mesh, r.first.primitive, r.first.vertex,
                      int32_t(r.count)})
      runs.push_back(v);
  w.putArray(runs);
  w.putArray(m.ordinals);
  return w.take();
}

SourceMap decodeSourceMap(std::span<const uint8_t> bytes, const std::string &context) {
  ByteReader r(bytes, context);
  SourceMap m;
  const auto runs = r.getArray<int32_t>("runs", limits::kChunkElements);
  if (runs.size() % 6 != 0)
    r.fail("runs", "not 6 values per run");
  for (size_t i = 0; i < runs.size(); i += 6) {
    const int32_t *v = &runs[i];
    if (v[0] < 0 || v[1] < 0 || v[2] < 0 || v[3] < 0 || v[4] < 0 || v[5] < 1 ||
        int64_t(v[4]) + v[5] - 1 > INT32_MAX)
      r.fail("runs", "run " + std::to_string(i / 6) + " is out of range");
    m.runs.push_back({{v[0], v[1], v[2], v[3], v[4]}, uint32_t(v[5])});
  }
  const uint64_t total = m.runVertices(); // distinct sources: at most the mesh's vertices
  if (total > limits::kVertices)
    r.fail("runs", std::to_string(total) + " vertices in all, more than a character has (" +
                       std::to_string(limits::kVertices) + ")");
  m.ordinals = r.getArray<uint32_t>("ordinals", limits::kChunkElements);
  for (size_t v = 0; v < m.ordinals.size(); ++v)
    if (m.ordinals[v] != SourceMap::kMade && m.ordinals[v] >= total)
      r.fail("ordinals", "vertex " + std::to_string(v) + " points past the runs");
  r.expectEnd();
  return m;
}

} // namespace crowd::pack
