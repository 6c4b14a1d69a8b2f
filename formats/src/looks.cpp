#include "crowd/formats/bytes.h"
#include "crowd/formats/chunks.h"

namespace crowd::pack {

std::vector<uint8_t> encode(const Looks &l) {
  ByteWriter w;
  w.putArray(l.colours);
  w.putArray(l.textured);
  return w.take();
}

Looks decodeLooks(std::span<const uint8_t> bytes, const std::string &context) {
  ByteReader r(bytes, context);
  Looks l;
  l.colours = r.getArray<float>("colours", 65535 * 4);
  for (float f : l.colours)
    if (!(f >= 0 && f <= 1))
      r.fail("colours", "a value is not in 0..1");
  l.textured = r.getArray<uint8_t>("textured", 65535);
  if (l.colours.size() != l.textured.size() * 4)
    r.fail("colours", "not 4 per sub-mesh");
  for (uint8_t t : l.textured)
    if (t > 1)
      r.fail("textured", "a value is not 0 or 1");
  r.expectEnd();
  return l;
}

} // namespace crowd::pack
