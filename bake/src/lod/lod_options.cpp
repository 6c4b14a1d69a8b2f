// The LOD bake's options checked (a manifest's reader needs this alone).
#include "crowd/bake/lod_bake.h"

#include "crowd/formats/error.h"

namespace crowd {

void LodOptions::validate() const {
  if (!(floorFraction >= 0 && floorFraction <= 1))
    throw Error("floor: must be in [0, 1]");
  if (poses > 1024)
    throw Error("poses: must be an integer in [0, 1024]");
  if (!(seamBudget >= 0 && seamBudget <= 442)) // 442: 255 x sqrt(3), black to white
    throw Error("seam budget: must be in [0, 442] (8-bit RGB distance)");
  if (!(maxNormalDeviationDeg > 0 && maxNormalDeviationDeg <= 180))
    throw Error("max normal deviation: must be in (0, 180] degrees");
}

} // namespace crowd
