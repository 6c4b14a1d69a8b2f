// The SKIN chunk: four joint ids and weights per vertex.
#include "crowd/formats/chunks.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "chunk_checks.h"
#include "crowd/formats/bytes.h"
#include "crowd/formats/error.h"

namespace crowd::pack {

using namespace checks;

std::vector<uint8_t> encode(const SkinTexture &t) {
  ByteWriter w;
  w.put<uint32_t>(t.width);
  w.put<uint32_t>(t.height);
  w.put<uint32_t>(t.vertexCount);
  w.putArray(t.texels);
  return w.take();
}

SkinTexture decodeSkinTexture(std::span<const uint8_t> bytes, const std::string &context) {
  ByteReader r(bytes, context);
  SkinTexture t;
  readSize(r, t.width, t.height, kMaxTextureSide);
  t.vertexCount = r.get<uint32_t>("vertex count");
  if (t.width % 2 != 0)
    r.fail("width", std::to_string(t.width) + " is odd: a vertex's two texels share a row");
  if (uint64_t(t.vertexCount) * 2 > uint64_t(t.width) * t.height)
    r.fail("vertex count", "does not fit in the texture");
  uint64_t expected = uint64_t(t.width) * t.height * 4;
  t.texels = r.getArray<float>("texels", expected);
  if (t.texels.size() != expected)
    r.fail("texels", "size does not match width x height");
  checkFinite(r, t.texels, "texels");
  for (uint32_t v = 0; v < t.vertexCount; ++v) {
    const float *ids = &t.texels[size_t(v) * 8];
    const float *w = ids + 4;
    for (int k = 0; k < 4; ++k) {
      if (ids[k] < 0 || ids[k] != std::floor(ids[k]))
        r.fail("texels", "vertex " + std::to_string(v) + " has joint id " + std::to_string(ids[k]));
      if (w[k] < 0 || w[k] > 1)
        r.fail("texels", "vertex " + std::to_string(v) + " has weight " + std::to_string(w[k]));
    }
  }
  r.expectEnd();
  return t;
}

} // namespace crowd::pack
