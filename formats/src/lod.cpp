// The LODS chunk: the continuous LOD arrays.
#include "crowd/formats/chunks.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "chunk_checks.h"
#include "crowd/formats/bytes.h"
#include "crowd/formats/error.h"

namespace crowd::pack {

using namespace checks;

std::vector<uint8_t> encode(const Lod &l) {
  ByteWriter w;
  w.put<uint32_t>(l.floorVertices);
  w.putArray(l.collapse);
  w.putArray(l.error);
  w.putArray(l.triangleCounts);
  return w.take();
}

Lod decodeLod(std::span<const uint8_t> bytes, const std::string &context) {
  ByteReader r(bytes, context);
  Lod l;
  l.floorVertices = r.get<uint32_t>("floor vertices");
  l.collapse = r.getArray<uint32_t>("collapse", kMaxElements);
  l.error = r.getArray<float>("error", kMaxElements);
  l.triangleCounts = r.getArray<uint32_t>("triangle counts", kMaxElements);
  const size_t n = l.collapse.size();
  if (n == 0 || l.floorVertices == 0 || l.floorVertices > n)
    r.fail("floor vertices", std::to_string(l.floorVertices) + " of " + std::to_string(n));
  for (size_t k = 0; k < n; ++k)
    if (k < l.floorVertices ? l.collapse[k] != k : l.collapse[k] >= k)
      r.fail("collapse",
             "vertex " + std::to_string(k) + " collapses into " + std::to_string(l.collapse[k]));
  if (l.error.size() != n)
    r.fail("error", "count differs from the collapse map");
  checkFinite(r, l.error, "error");
  if (l.triangleCounts.empty() || l.triangleCounts.size() % (n + 1) != 0)
    r.fail("triangle counts", "not whole rows of vertex count + 1");
  for (size_t i = 0; i < l.triangleCounts.size(); ++i)
    if (i % (n + 1) != 0 && l.triangleCounts[i] < l.triangleCounts[i - 1])
      r.fail("triangle counts", "decrease at entry " + std::to_string(i));
  r.expectEnd();
  return l;
}

} // namespace crowd::pack
