// The terrain chunk (TERR): an environment baked for a crowd (Tecchia, Loscos &
// Chrysanthou). On a grid of square cells seen from above: the top surface's height (their §2,
// what agents walk and collide on), whether an agent may stand there, and the shadow height for
// one directional light (their §4.5: a point of a cell below that height is in the shadow of
// something between it and the light). Plus the environment's mesh, for drawing it.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "crowd/formats/chunks.h"

namespace crowd::pack {

inline constexpr uint32_t kTerrain = fourcc("TERR");
inline constexpr uint32_t kTerrainVersion = 1;

// What an agent finds on a cell.
enum class Ground : uint8_t {
  None = 0,     // no surface at all (outside the environment's meshes)
  Blocked = 1,  // too steep, or not reachable from the walkable area by steps (a roof)
  Walkable = 2, // the largest area agents reach from cell to cell by steps
};

struct Terrain {
  float originX = 0, originZ = 0;        // world x and z of cell (0, 0)'s outer corner
  float cell = 0;                        // a cell's side (model units); cells run along +x, then +z
  uint32_t width = 0, depth = 0;         // cells along x and along z
  std::array<float, 3> light{};          // unit direction towards the light (y > 0)
  float stepHeight = 0, maxSlopeDeg = 0; // the walkable rule the bake applied
  // Per cell, index z * width + x:
  std::vector<float> heights;       // top surface; the environment's lowest point where None
  std::vector<uint8_t> ground;      // Ground
  std::vector<float> shadowHeights; // >= heights: below it a point of the cell is in shadow
  // The environment's mesh in world space: xyz per vertex, unit normals, RGBA8 colours (its
  // material's base colour), triangles.
  std::vector<float> positions, normals;
  std::vector<uint8_t> colours;
  std::vector<uint32_t> indices;

  size_t cells() const { return size_t(width) * depth; }
  size_t cellIndex(uint32_t x, uint32_t z) const { return size_t(z) * width + x; }
};

std::vector<uint8_t> encode(const Terrain &);
// Checks every size against the grid and the limits, every value finite, the light above the
// horizon, ground codes known, shadow heights not below the surface, indices in range.
Terrain decodeTerrain(std::span<const uint8_t>, const std::string &context);

} // namespace crowd::pack
