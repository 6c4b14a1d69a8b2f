// Terrain bake (Tecchia, Loscos & Chrysanthou, §2 and §4.5): an environment's static
// meshes rasterized from straight above into a grid of cells: the top surface's height, a
// walkable map (a cell is walkable where its surface is no steeper than maxSlopeDeg and agents
// reach it from the largest such area by steps of at most stepHeight), and the shadow height map
// for one directional light. Data in (a Character of rigid parts), a pack::Terrain out.
#pragma once
#include <cstdint>

#include <glm/glm.hpp>

#include "crowd/bake/character.h"
#include "crowd/bake/report.h"
#include "crowd/formats/terrain.h"

namespace crowd {

struct TerrainOptions {
  double cell = 0.25;              // a cell's side, model units (metres for glTF)
  glm::dvec3 light{0.4, 1.0, 0.3}; // towards the light (any length; y > 0: above the horizon)
  double stepHeight = 0.3;         // the highest step an agent climbs or descends
  double maxSlopeDeg = 35;         // the steepest surface an agent stands on
  int threads = 0;                 // 0: all cores; the bytes never depend on it
  void validate() const;           // throws crowd::Error naming the first field out of range
};

struct TerrainBakeResult {
  pack::Terrain terrain;
  uint64_t walkable = 0, blocked = 0, empty = 0; // cells by Ground
  uint64_t unreachable = 0;      // of the blocked: flat enough, but no step leads there (roofs)
  uint64_t walkableInShadow = 0; // walkable cells whose surface is in shadow
  double maxShadowDepth = 0;     // the largest shadow height above its surface (model units)
};

// Throws crowd::Error when the environment is empty, not finite, larger than limits::
// kTerrainCells at this cell size, or has no walkable cell.
TerrainBakeResult bakeTerrain(const Character &environment, const TerrainOptions &options,
                              Reporter &reporter);

} // namespace crowd
