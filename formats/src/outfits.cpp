#include <cmath>

#include "crowd/formats/bytes.h"
#include "crowd/formats/chunks.h"
#include "crowd/formats/error.h"

namespace crowd::pack {

const char *name(Coverage c) {
  return c == Coverage::Visible ? "visible" : c == Coverage::Hidden ? "hidden" : "partial";
}

std::vector<uint8_t> encode(const Outfits &o) {
  ByteWriter w;
  w.put<uint32_t>(o.bodySubMeshes);
  w.putArray(o.colours);
  w.putArray(o.textured);
  w.put<uint32_t>(uint32_t(o.outfits.size()));
  for (const auto &outfit : o.outfits) {
    w.putString(outfit.name);
    std::vector<uint8_t> coverage;
    for (Coverage c : outfit.coverage)
      coverage.push_back(uint8_t(c));
    w.putArray(coverage);
    w.putArray(outfit.subMeshes);
  }
  return w.take();
}

Outfits decodeOutfits(std::span<const uint8_t> bytes, const std::string &context) {
  ByteReader r(bytes, context);
  Outfits o;
  o.bodySubMeshes = r.get<uint32_t>("body sub-meshes");
  if (o.bodySubMeshes == 0 || o.bodySubMeshes > 65535)
    r.fail("body sub-meshes", std::to_string(o.bodySubMeshes) + " is out of range 1..65535");
  o.colours = r.getArray<float>("colours", 65535 * 4);
  for (float f : o.colours)
    if (!std::isfinite(f))
      r.fail("colours", "a value is not finite");
  o.textured = r.getArray<uint8_t>("textured", 65535);
  if (o.colours.size() != o.textured.size() * 4)
    r.fail("colours", "not 4 per sub-mesh");
  const uint32_t n = r.get<uint32_t>("outfit count");
  if (n == 0 || n > 65535)
    r.fail("outfit count", std::to_string(n) + " is out of range 1..65535");
  for (uint32_t i = 0; i < n; ++i) {
    Outfits::Outfit outfit;
    outfit.name = r.getString("outfit name");
    for (uint8_t c : r.getArray<uint8_t>("coverage", o.bodySubMeshes)) {
      if (c > uint8_t(Coverage::Partial))
        r.fail("coverage", "outfit '" + outfit.name + "': unknown value " + std::to_string(c));
      outfit.coverage.push_back(Coverage(c));
    }
    if (outfit.coverage.size() != o.bodySubMeshes)
      r.fail("coverage", "outfit '" + outfit.name + "': not one per body sub-mesh");
    outfit.subMeshes = r.getArray<uint32_t>("sub-meshes", 65535);
    for (size_t k = 1; k < outfit.subMeshes.size(); ++k)
      if (outfit.subMeshes[k] <= outfit.subMeshes[k - 1])
        r.fail("sub-meshes", "outfit '" + outfit.name + "': not increasing");
    o.outfits.push_back(std::move(outfit));
  }
  r.expectEnd();
  return o;
}

void checkOutfits(const Outfits &o, const Mesh &mesh, const std::string &context) {
  const size_t count = mesh.subMeshes.size();
  if (o.textured.size() != count || o.bodySubMeshes > count)
    throw Error(context + ", field 'textured': " + std::to_string(o.textured.size()) +
                " sub-meshes described, the mesh has " + std::to_string(count));
  for (const auto &outfit : o.outfits) {
    std::vector<bool> drawn(count, false);
    for (uint32_t s : outfit.subMeshes) {
      if (s >= count)
        throw Error(context + ", field 'sub-meshes': outfit '" + outfit.name + "' draws sub-mesh " +
                    std::to_string(s) + " of " + std::to_string(count));
      drawn[s] = true;
    }
    for (size_t s = 0; s < o.bodySubMeshes; ++s)
      if (drawn[s] != (outfit.coverage[s] == Coverage::Visible))
        throw Error(context + ", field 'coverage': outfit '" + outfit.name + "' marks sub-mesh '" +
                    mesh.subMeshes[s].name + "' " + name(outfit.coverage[s]) + " but " +
                    (drawn[s] ? "draws" : "does not draw") + " it");
  }
}

} // namespace crowd::pack
