#include "crowd/bake/terrain_bake.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "crowd/bake/evaluate.h"
#include "crowd/bake/parallel.h"
#include "crowd/bake/raster.h"
#include "crowd/formats/error.h"
#include "crowd/formats/limits.h"

namespace crowd {

namespace {

// The environment's mesh in world space, its normals turned with it (rigid parts ride their
// nodes; a skinned environment is taken in its rest pose).
void worldMesh(const Character &c, pack::Terrain &t) {
  const auto joints = jointMatrices(c, nullptr, 0);
  const auto positions = posedPositions(c, nullptr, 0);
  const size_t n = positions.size();
  for (size_t v = 0; v < n; ++v)
    if (!std::isfinite(positions[v].x) || !std::isfinite(positions[v].y) ||
        !std::isfinite(positions[v].z))
      throw Error("environment: vertex " + std::to_string(v) + " is not finite in world space");
  t.positions.reserve(3 * n);
  t.normals.reserve(3 * n);
  for (size_t v = 0; v < n; ++v) {
    glm::dvec3 normal(0);
    for (int k = 0; k < 4; ++k) {
      const double w = c.mesh.weights[v][k];
      if (w > 0) // the inverse transpose keeps normals normal under non-uniform scale
        normal += w * (glm::transpose(glm::inverse(glm::dmat3(joints[c.mesh.joints[v][k]]))) *
                       glm::dvec3(c.mesh.normals[v]));
    }
    const double length = glm::length(normal);
    normal = length > 0 && std::isfinite(length) ? normal / length : glm::dvec3(0, 1, 0);
    for (int k = 0; k < 3; ++k) {
      t.positions.push_back(float(positions[v][k]));
      t.normals.push_back(float(normal[k]));
    }
  }
  t.colours.assign(4 * n, 255);
  for (const auto &part : c.mesh.parts)
    for (uint32_t i = part.firstIndex; i < part.firstIndex + part.indexCount; ++i)
      for (int k = 0; k < 4; ++k)
        t.colours[4 * size_t(c.mesh.indices[i]) + size_t(k)] =
            uint8_t(std::lround(std::clamp(double(part.colour[k]), 0.0, 1.0) * 255));
  t.indices = c.mesh.indices;
}

// Heights and the slope test from one orthographic view straight down: pixel (x, y) is cell
// (x, z = y), its centre at the cell's centre.
void rasterizeFromAbove(pack::Terrain &t, double lowest, double highest, const TerrainOptions &o,
                        std::vector<uint8_t> &standable) {
  std::vector<glm::vec3> positions(t.positions.size() / 3);
  for (size_t v = 0; v < positions.size(); ++v)
    positions[v] = {t.positions[3 * v], t.positions[3 * v + 1], t.positions[3 * v + 2]};
  const double halfX = 0.5 * t.width * o.cell, halfZ = 0.5 * t.depth * o.cell;
  const glm::dvec3 centre(t.originX + halfX, 0, t.originZ + halfZ);
  // Up on the image is -z, so row 0 is the lowest z and image right is +x.
  const auto camera =
      raster::orthographic({centre.x, highest + 1, centre.z}, {centre.x, lowest - 1, centre.z},
                           {0, 0, -1}, halfX, halfZ, 0.5, highest - lowest + 1.5);
  const raster::Image image = raster::rasterize(positions, t.indices, camera, int(t.width),
                                                int(t.depth), {false, o.threads});
  const double cosMax = std::cos(o.maxSlopeDeg * std::numbers::pi / 180);
  t.heights.assign(t.cells(), float(lowest));
  t.ground.assign(t.cells(), uint8_t(pack::Ground::None));
  standable.assign(t.cells(), 0);
  for (size_t i = 0; i < t.cells(); ++i) {
    if (image.triangle[i] < 0)
      continue;
    t.heights[i] = raster::interpolate(image, i, positions, t.indices).y;
    t.ground[i] = uint8_t(pack::Ground::Blocked);
    const size_t tri = size_t(image.triangle[i]) * 3;
    const glm::dvec3 a(positions[t.indices[tri]]), b(positions[t.indices[tri + 1]]),
        c(positions[t.indices[tri + 2]]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double length = glm::length(n);
    standable[i] = length > 0 && std::abs(n.y) / length >= cosMax - 1e-12;
  }
}

// Walkable: the largest 4-connected area of standable cells between which every step is at most
// stepHeight (the first in cell order among equals). Returns the standable cells left out.
uint64_t markWalkable(pack::Terrain &t, const std::vector<uint8_t> &standable, double step) {
  std::vector<uint32_t> component(t.cells(), 0);
  std::vector<size_t> stack, sizes{0};
  size_t best = 0;
  for (size_t seed = 0; seed < t.cells(); ++seed) {
    if (!standable[seed] || component[seed])
      continue;
    const uint32_t id = uint32_t(sizes.size());
    size_t size = 0;
    stack = {seed};
    component[seed] = id;
    while (!stack.empty()) {
      const size_t i = stack.back();
      stack.pop_back();
      ++size;
      const uint32_t x = uint32_t(i % t.width), z = uint32_t(i / t.width);
      auto visit = [&](size_t j) {
        if (standable[j] && !component[j] && std::abs(double(t.heights[j]) - t.heights[i]) <= step)
          component[j] = id, stack.push_back(j);
      };
      if (x > 0)
        visit(i - 1);
      if (x + 1 < t.width)
        visit(i + 1);
      if (z > 0)
        visit(i - t.width);
      if (z + 1 < t.depth)
        visit(i + t.width);
    }
    sizes.push_back(size);
    if (size > sizes[best])
      best = sizes.size() - 1;
  }
  uint64_t unreachable = 0;
  for (size_t i = 0; i < t.cells(); ++i) {
    if (best && component[i] == best)
      t.ground[i] = uint8_t(pack::Ground::Walkable);
    else
      unreachable += standable[i];
  }
  return unreachable;
}

// §4.5: a point at height y over cell p is in shadow when the ray from it towards the light
// passes under the surface somewhere, i.e. y < H(p + r d) - r tan(elevation) for some horizontal
// distance r > 0 along the light's horizontal direction d. The shadow height is the largest such
// bound, marched in half-cell steps over the height map (nearest cell) until the ray clears the
// highest surface or leaves the grid, and never below the cell's own surface.
void shadowHeights(pack::Terrain &t, double highest, const TerrainOptions &o) {
  const glm::dvec3 l = glm::normalize(o.light);
  const double horizontal = std::hypot(l.x, l.z);
  t.shadowHeights = t.heights;
  if (horizontal < 1e-9) // the light straight above: nothing in a height map shades another cell
    return;
  const double dx = l.x / horizontal, dz = l.z / horizontal, rise = l.y / horizontal;
  const double stepLength = 0.5 * o.cell;
  parallelFor(t.depth, o.threads, [&](size_t z) {
    for (uint32_t x = 0; x < t.width; ++x) {
      const size_t i = t.cellIndex(x, uint32_t(z));
      const double px = x + 0.5, pz = double(z) + 0.5;
      double shadow = t.heights[i];
      for (double r = stepLength;; r += stepLength) {
        const double drop = r * rise;
        if (shadow + drop >= highest) // no surface further on can reach above it
          break;
        const double cx = px + r * dx / o.cell, cz = pz + r * dz / o.cell;
        if (cx < 0 || cz < 0 || cx >= t.width || cz >= t.depth)
          break;
        const double h = t.heights[t.cellIndex(uint32_t(cx), uint32_t(cz))] - drop;
        shadow = std::max(shadow, h);
      }
      t.shadowHeights[i] = float(shadow);
    }
  });
}

} // namespace

TerrainBakeResult bakeTerrain(const Character &c, const TerrainOptions &o, Reporter &reporter) {
  o.validate();
  if (c.mesh.indices.empty())
    throw Error("environment: no triangles to stand on");
  TerrainBakeResult result;
  pack::Terrain &t = result.terrain;
  worldMesh(c, t);
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (size_t v = 0; v < t.positions.size(); v += 3)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], double(t.positions[v + size_t(k)]));
      hi[k] = std::max(hi[k], double(t.positions[v + size_t(k)]));
    }
  const double cellsX = std::ceil((hi.x - lo.x) / o.cell),
               cellsZ = std::ceil((hi.z - lo.z) / o.cell);
  if (!(std::max(cellsX, 1.0) * std::max(cellsZ, 1.0) <= double(limits::kTerrainCells))) {
    char line[200];
    std::snprintf(line, sizeof line,
                  "environment: %g x %g model units at a cell of %g needs more than %llu cells "
                  "(raise --cell)",
                  hi.x - lo.x, hi.z - lo.z, o.cell,
                  static_cast<unsigned long long>(limits::kTerrainCells));
    throw Error(line);
  }
  t.width = uint32_t(std::max(cellsX, 1.0));
  t.depth = uint32_t(std::max(cellsZ, 1.0));
  t.cell = float(o.cell);
  t.originX = float(lo.x), t.originZ = float(lo.z);
  const glm::dvec3 l = glm::normalize(o.light);
  t.light = {float(l.x), float(l.y), float(l.z)};
  t.stepHeight = float(o.stepHeight);
  t.maxSlopeDeg = float(o.maxSlopeDeg);

  std::vector<uint8_t> standable;
  rasterizeFromAbove(t, lo.y, hi.y, o, standable);
  result.unreachable = markWalkable(t, standable, o.stepHeight);
  shadowHeights(t, hi.y, o);
  for (size_t i = 0; i < t.cells(); ++i) {
    const auto g = pack::Ground(t.ground[i]);
    result.walkable += g == pack::Ground::Walkable;
    result.blocked += g == pack::Ground::Blocked;
    result.empty += g == pack::Ground::None;
    if (g == pack::Ground::Walkable && t.shadowHeights[i] > t.heights[i]) {
      ++result.walkableInShadow;
      result.maxShadowDepth =
          std::max(result.maxShadowDepth, double(t.shadowHeights[i]) - t.heights[i]);
    }
  }
  char line[200];
  if (result.walkable == 0) {
    std::snprintf(line, sizeof line,
                  "environment: no walkable cell (no surface within %g degrees of level; raise "
                  "--max-slope)",
                  o.maxSlopeDeg);
    throw Error(line);
  }
  if (result.unreachable) {
    std::snprintf(line, sizeof line,
                  "%llu cells are flat enough to stand on but no step of at most %g leads there "
                  "from the walkable area (roofs, raised floors): blocked",
                  static_cast<unsigned long long>(result.unreachable), o.stepHeight);
    reporter.warn("terrain_unreachable", line, result.unreachable);
  }
  return result;
}

} // namespace crowd
