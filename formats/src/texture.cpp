// The TEXR chunk: the diffuse texture, RGBA8.
#include "crowd/formats/chunks.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "chunk_checks.h"
#include "crowd/formats/bytes.h"
#include "crowd/formats/error.h"

namespace crowd::pack {

using namespace checks;

std::vector<uint8_t> encode(const Texture &t) {
  ByteWriter w;
  w.put<uint32_t>(t.width);
  w.put<uint32_t>(t.height);
  w.putArray(t.rgba);
  return w.take();
}

Texture decodeTexture(std::span<const uint8_t> bytes, const std::string &context) {
  ByteReader r(bytes, context);
  Texture t;
  readSize(r, t.width, t.height, 16384);
  uint64_t expected = uint64_t(t.width) * t.height * 4;
  t.rgba = r.getArray<uint8_t>("texels", expected);
  if (t.rgba.size() != expected)
    r.fail("texels", "size does not match width x height x 4");
  r.expectEnd();
  return t;
}

} // namespace crowd::pack
