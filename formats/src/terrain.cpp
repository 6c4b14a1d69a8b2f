#include "crowd/formats/terrain.h"

#include <cmath>

#include "crowd/formats/bytes.h"
#include "crowd/formats/limits.h"

namespace crowd::pack {

std::vector<uint8_t> encode(const Terrain &t) {
  ByteWriter w;
  for (float f : {t.originX, t.originZ, t.cell})
    w.put<float>(f);
  w.put<uint32_t>(t.width);
  w.put<uint32_t>(t.depth);
  for (float f : t.light)
    w.put<float>(f);
  w.put<float>(t.stepHeight);
  w.put<float>(t.maxSlopeDeg);
  w.putArray(t.heights);
  w.putArray(t.ground);
  w.putArray(t.shadowHeights);
  w.putArray(t.positions);
  w.putArray(t.normals);
  w.putArray(t.colours);
  w.putArray(t.indices);
  return w.take();
}

namespace {

void checkFinite(ByteReader &r, const std::vector<float> &values, const char *field) {
  for (size_t i = 0; i < values.size(); ++i)
    if (!std::isfinite(values[i]))
      r.fail(field, "value " + std::to_string(i) + " is not finite");
}

} // namespace

Terrain decodeTerrain(std::span<const uint8_t> bytes, const std::string &context) {
  ByteReader r(bytes, context);
  Terrain t;
  t.originX = r.get<float>("origin x");
  t.originZ = r.get<float>("origin z");
  t.cell = r.get<float>("cell");
  if (!std::isfinite(t.originX) || !std::isfinite(t.originZ))
    r.fail("origin", "not finite");
  if (!(t.cell > 0 && t.cell < 1e6f))
    r.fail("cell", "not in (0, 1e6)");
  t.width = r.get<uint32_t>("width");
  t.depth = r.get<uint32_t>("depth");
  if (t.width == 0 || t.depth == 0 || uint64_t(t.width) * t.depth > limits::kTerrainCells)
    r.fail("width",
           "the grid must have between 1 and " + std::to_string(limits::kTerrainCells) + " cells");
  double length = 0;
  for (auto &f : t.light) {
    f = r.get<float>("light");
    length += double(f) * f;
  }
  if (!(std::abs(length - 1) < 1e-3) || !(t.light[1] > 0))
    r.fail("light", "not a unit direction above the horizon");
  t.stepHeight = r.get<float>("step height");
  t.maxSlopeDeg = r.get<float>("max slope");
  if (!(t.stepHeight >= 0 && std::isfinite(t.stepHeight)) ||
      !(t.maxSlopeDeg >= 0 && t.maxSlopeDeg <= 90))
    r.fail("step height", "the walkable rule is out of range");
  const size_t cells = t.cells();
  t.heights = r.getArray<float>("heights", cells);
  t.ground = r.getArray<uint8_t>("ground", cells);
  t.shadowHeights = r.getArray<float>("shadow heights", cells);
  if (t.heights.size() != cells || t.ground.size() != cells || t.shadowHeights.size() != cells)
    r.fail("heights", "the maps must hold width x depth cells");
  checkFinite(r, t.heights, "heights");
  checkFinite(r, t.shadowHeights, "shadow heights");
  for (size_t i = 0; i < cells; ++i) {
    if (t.ground[i] > uint8_t(Ground::Walkable))
      r.fail("ground", "cell " + std::to_string(i) + " has an unknown code");
    if (t.shadowHeights[i] < t.heights[i])
      r.fail("shadow heights", "cell " + std::to_string(i) + " is below its surface");
  }
  t.positions = r.getArray<float>("positions", 3 * limits::kVertices);
  t.normals = r.getArray<float>("normals", 3 * limits::kVertices);
  t.colours = r.getArray<uint8_t>("colours", 4 * limits::kVertices);
  const size_t vertices = t.positions.size() / 3;
  if (t.positions.size() % 3 || t.normals.size() != t.positions.size() ||
      t.colours.size() != 4 * vertices)
    r.fail("positions", "positions, normals and colours disagree on the vertex count");
  checkFinite(r, t.positions, "positions");
  checkFinite(r, t.normals, "normals");
  t.indices = r.getArray<uint32_t>("indices", 3 * limits::kTriangles);
  if (t.indices.size() % 3)
    r.fail("indices", "not whole triangles");
  for (uint32_t i : t.indices)
    if (i >= vertices)
      r.fail("indices",
             "index " + std::to_string(i) + " past the " + std::to_string(vertices) + " vertices");
  r.expectEnd();
  return t;
}

} // namespace crowd::pack
