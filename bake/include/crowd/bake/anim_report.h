// The error figures of an animation bake as every --report writes them (crowdbake anim, lod,
// outfits and build), so the keys cannot drift between commands.
#pragma once
#include <nlohmann/json.hpp>

#include "crowd/bake/anim_bake.h"

namespace crowd {

// One clip's errors: first the largest at any time measured, in millimetres at a 1.8 m character
// (`max_error_any_time_mm`) and as a fraction of the rest diagonal (`max_error_any_time`); then
// max and mean at frame times, mid-frame times and the seeded random times, as fractions of the
// diagonal and in model units.
nlohmann::ordered_json clipErrorsJson(const ClipAccuracy &a, const AnimBakeResult &r);

// Every precision's bytes and per-clip errors (the report's "precisions" list).
nlohmann::ordered_json precisionJson(const PrecisionAccuracy &pa, const AnimBakeResult &r);

// An animation bake's figures: its scale (diagonal, millimetres per model unit), the baked
// precision, each clip (name, frames, fps, start time, loop, errors) and every precision.
nlohmann::ordered_json animFigures(const AnimBakeResult &r);

} // namespace crowd
