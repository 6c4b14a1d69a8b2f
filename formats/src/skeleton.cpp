// The SKEL chunk: joint names, parents and inverse bind matrices.
#include "crowd/formats/chunks.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "chunk_checks.h"
#include "crowd/formats/bytes.h"
#include "crowd/formats/error.h"

namespace crowd::pack {

using namespace checks;

std::vector<uint8_t> encode(const Skeleton &s) {
  ByteWriter w;
  w.put<uint32_t>(uint32_t(s.names.size()));
  for (const auto &n : s.names)
    w.putString(n);
  w.putArray(s.parents);
  w.putArray(s.inverseBind);
  return w.take();
}

Skeleton decodeSkeleton(std::span<const uint8_t> bytes, const std::string &context) {
  ByteReader r(bytes, context);
  Skeleton s;
  uint32_t n = r.get<uint32_t>("joint count");
  if (n == 0 || n > 65535)
    r.fail("joint count", std::to_string(n) + " is out of range 1..65535");
  for (uint32_t i = 0; i < n; ++i)
    s.names.push_back(r.getString("joint name"));
  s.parents = r.getArray<int32_t>("parents", n);
  s.inverseBind = r.getArray<float>("inverse bind matrices", uint64_t(n) * 16);
  if (s.parents.size() != n)
    r.fail("parents", "count differs from joint count");
  if (s.inverseBind.size() != size_t(n) * 16)
    r.fail("inverse bind matrices", "not 16 per joint");
  for (uint32_t i = 0; i < n; ++i)
    if (s.parents[i] < -1 || s.parents[i] >= int32_t(i))
      r.fail("parents", "joint " + std::to_string(i) + " has parent " +
                            std::to_string(s.parents[i]) + " (must be -1 or a lower index)");
  checkFinite(r, s.inverseBind, "inverse bind matrices");
  r.expectEnd();
  return s;
}

} // namespace crowd::pack
