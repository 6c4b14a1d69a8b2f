// glTF primitive topologies (the spec's mesh.primitive.mode): which a character's mesh takes, and
// strips and fans turned into the triangle lists every bake works on.
#pragma once
#include <cstdint>
#include <vector>

namespace crowd::gltf {

enum Mode : int {
  kPoints = 0,
  kLines = 1,
  kLineLoop = 2,
  kLineStrip = 3,
  kTriangles = 4,
  kTriangleStrip = 5,
  kTriangleFan = 6
};

// Points and lines draw no surface: a character's mesh skips them (with a warning).
inline bool drawsTriangles(int mode) { return mode < 0 || mode >= kTriangles; } // -1: unset

// The triangles a primitive of `mode` (triangles, strip or fan) draws from `count` indices.
inline uint64_t triangleCount(int mode, uint64_t count) {
  if (mode == kTriangleStrip || mode == kTriangleFan)
    return count < 3 ? 0 : count - 2;
  return count / 3;
}

// A strip's or fan's indices as a triangle list, triangle i wound as the spec draws it: a strip's
// {v_i, v_i+1, v_i+2} (odd i: {v_i, v_i+2, v_i+1}), a fan's {v_i+1, v_i+2, v_0}; a list is
// returned as it is. A strip's or fan's triangle that repeats an index is left out: it draws
// nothing, and it is how exporters join several strips into one (degenerate triangles), which
// would otherwise reach every bake as faces of no area on the joined vertices.
inline std::vector<uint32_t> asTriangleList(int mode, std::vector<uint32_t> idx) {
  if (mode != kTriangleStrip && mode != kTriangleFan)
    return idx;
  std::vector<uint32_t> list;
  for (size_t i = 0; i + 2 < idx.size(); ++i) {
    const uint32_t a = mode == kTriangleFan ? idx[i + 1] : idx[i];
    const uint32_t b = mode == kTriangleFan ? idx[i + 2] : idx[i + 1 + i % 2];
    const uint32_t c = mode == kTriangleFan ? idx[0] : idx[i + 2 - i % 2];
    if (a != b && b != c && c != a)
      list.insert(list.end(), {a, b, c});
  }
  return list;
}

} // namespace crowd::gltf
