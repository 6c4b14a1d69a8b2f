// The outfit bake's options checked (a manifest's reader needs this alone).
#include "crowd/bake/outfit_bake.h"

#include "crowd/formats/error.h"

namespace crowd {

void OutfitOptions::setAnimation(const AnimBakeOptions &a) {
  anim = a;
  if (a.fps > 0)
    visibility.fps = a.fps;
}

void OutfitOptions::validate() const {
  const auto &v = visibility;
  if (regions != "material" && regions != "joint")
    throw Error("regions: must be material or joint, got '" + regions + "'");
  if (!(minSaving >= 0 && minSaving <= 1))
    throw Error("min-saving: must be in [0, 1]");
  if (v.frameStep < 1 || v.frameStep > 100000)
    throw Error("frame-step: must be in [1, 100000]");
  if (v.rays < 1 || v.rays > 4096)
    throw Error("rays: must be in [1, 4096]");
  if (v.points != 1 && v.points != 4)
    throw Error("points: must be 1 or 4");
  if (v.ring > 64)
    throw Error("ring: must be in [0, 64]");
  if (check > 100000)
    throw Error("check: must be in [0, 100000]");
  if (!(v.fps > 0 && v.fps <= 1000))
    throw Error("fps: must be in (0, 1000]");
  anim.validate();
  if (lod)
    lod->validate();
}

} // namespace crowd
