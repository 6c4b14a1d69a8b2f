// The MESH chunk: bind-pose vertices, triangles and sub-meshes.
#include "crowd/formats/chunks.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "chunk_checks.h"
#include "crowd/formats/bytes.h"
#include "crowd/formats/error.h"

namespace crowd::pack {

using namespace checks;

std::vector<uint8_t> encode(const Mesh &m) {
  ByteWriter w;
  w.putArray(m.positions);
  w.putArray(m.normals);
  w.putArray(m.uvs);
  w.putArray(m.indices);
  w.put<uint32_t>(uint32_t(m.subMeshes.size()));
  for (const auto &s : m.subMeshes) {
    w.putString(s.name);
    w.put<uint32_t>(s.firstIndex);
    w.put<uint32_t>(s.indexCount);
  }
  for (float f : m.boundingSphere)
    w.put<float>(f);
  return w.take();
}

Mesh decodeMesh(std::span<const uint8_t> bytes, const std::string &context) {
  ByteReader r(bytes, context);
  Mesh m;
  m.positions = r.getArray<float>("positions", kMaxElements);
  m.normals = r.getArray<float>("normals", kMaxElements);
  m.uvs = r.getArray<float>("uvs", kMaxElements);
  m.indices = r.getArray<uint32_t>("indices", kMaxElements);
  size_t vc = m.positions.size() / 3;
  if (m.positions.size() % 3 != 0 || vc == 0)
    r.fail("positions", "not a non-empty xyz array");
  if (m.normals.size() != m.positions.size())
    r.fail("normals", "count differs from positions");
  if (!m.uvs.empty() && m.uvs.size() != vc * 2)
    r.fail("uvs", "count differs from vertices");
  if (m.indices.empty() || m.indices.size() % 3 != 0)
    r.fail("indices", "not a non-empty triangle list");
  for (size_t i = 0; i < m.indices.size(); ++i)
    if (m.indices[i] >= vc)
      r.fail("indices", "index " + std::to_string(i) + " = " + std::to_string(m.indices[i]) +
                            " >= vertex count " + std::to_string(vc));
  checkFinite(r, m.positions, "positions");
  checkFinite(r, m.normals, "normals");
  checkFinite(r, m.uvs, "uvs");
  uint32_t n = r.get<uint32_t>("sub-mesh count");
  if (n == 0 || n > 65535)
    r.fail("sub-mesh count", std::to_string(n) + " is out of range");
  for (uint32_t i = 0; i < n; ++i) {
    SubMesh s;
    s.name = r.getString("sub-mesh name");
    s.firstIndex = r.get<uint32_t>("sub-mesh first index");
    s.indexCount = r.get<uint32_t>("sub-mesh index count");
    if (s.firstIndex % 3 != 0 || s.indexCount % 3 != 0 ||
        uint64_t(s.firstIndex) + s.indexCount > m.indices.size())
      r.fail("sub-mesh range", "sub-mesh '" + s.name + "' has a bad index range");
    m.subMeshes.push_back(s);
  }
  for (float &f : m.boundingSphere)
    f = r.get<float>("bounding sphere");
  if (!(m.boundingSphere[3] >= 0) || !std::isfinite(m.boundingSphere[0] + m.boundingSphere[1] +
                                                    m.boundingSphere[2] + m.boundingSphere[3]))
    r.fail("bounding sphere", "not finite or negative radius");
  r.expectEnd();
  return m;
}

} // namespace crowd::pack
