// The impostor bake's options checked (a manifest's reader needs this alone).
#include "crowd/bake/impostor_bake.h"

#include <cmath>

#include "crowd/formats/error.h"
#include "crowd/formats/limits.h"

namespace crowd {

void ImpostorOptions::validate() const {
  if (frames == 0 || frames > 4096)
    throw Error("frames: must be in 1..4096");
  if (azimuths == 0 || azimuths > 256 || elevations == 0 || elevations > 64)
    throw Error("views: must be AxE with A in 1..256 and E in 1..64");
  if (texels < 4 || texels > 4096)
    throw Error("texels: must be in 4..4096");
  if (mirror && (frames % 2 != 0 || azimuths % 2 != 0))
    throw Error("mirror: needs an even number of frames and of azimuths");
  if (threads < 0 || threads > 1024)
    throw Error("threads: must be in [0, 1024]");
  if (!(switchDistance >= 0) || !std::isfinite(switchDistance))
    throw Error("switch distance: must be a finite number >= 0");
  if (screenHeight < 16 || screenHeight > limits::kScreenSide)
    throw Error("screen height: must be in [16, " + std::to_string(limits::kScreenSide) + "]");
  if (!(fovDegrees >= 1 && fovDegrees <= 179))
    throw Error("fov: must be in [1, 179] degrees");
}

} // namespace crowd
