// The terrain bake's options checked (a manifest's reader needs this alone).
#include "crowd/bake/terrain_bake.h"

#include <cmath>

#include "crowd/formats/error.h"

namespace crowd {

void TerrainOptions::validate() const {
  if (!(cell > 0 && cell <= 1000))
    throw Error("terrain option 'cell' must be in (0, 1000] model units");
  const double length = glm::length(light);
  if (!std::isfinite(length) || !(light.y > 1e-6 * length))
    throw Error("terrain option 'light' must point above the horizon (y > 0)");
  if (!(stepHeight >= 0 && stepHeight <= 1000))
    throw Error("terrain option 'step' must be in [0, 1000] model units");
  if (!(maxSlopeDeg >= 0 && maxSlopeDeg < 90))
    throw Error("terrain option 'max_slope' must be in [0, 90) degrees");
  if (threads < 0)
    throw Error("terrain option 'threads' must be 0 (all cores) or more");
}

} // namespace crowd
