// Test helper: a flat, walkable terrain of `width` x `depth` cells of 0.25 m from (0, 0), lit
// from straight above, with the terrain bake's default step height: what the agents' and the
// world's tests shape by hand.
#pragma once
#include <cstdint>

#include "crowd/formats/terrain.h"

namespace crowd::test {

inline pack::Terrain flatTerrain(uint32_t width, uint32_t depth) {
  pack::Terrain t;
  t.cell = 0.25f;
  t.width = width, t.depth = depth;
  t.light = {0, 1, 0};
  t.stepHeight = 0.3f, t.maxSlopeDeg = 35;
  t.heights.assign(t.cells(), 0);
  t.shadowHeights.assign(t.cells(), 0);
  t.ground.assign(t.cells(), uint8_t(pack::Ground::Walkable));
  return t;
}

} // namespace crowd::test
