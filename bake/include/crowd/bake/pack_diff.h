// crowdbake diff: is a new pack the same as a golden one, within what tolerance, and where does it
// differ? Modelled on OpenImageIO's idiff. Chunks are matched by type (and, for impostors and
// cloth loops, by what they show) and compared in the units a user thinks in: the animation as
// vertex displacement after skinning with the player's math, in mm at a 1.8 m character, at
// every frame and mid-frame of both packs; the mesh in mm, degrees and UV units; atlases
// idiff-style. Each comparison is identical, within the warn tolerance, within the fail
// tolerance (a warning) or over it (a failure); provenance differences are listed, never failing.
#pragma once
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "crowd/formats/container.h"

namespace crowd {

// Every tolerance, with its default: a pair (warn, fail) where a change up to `warn` passes and
// one over `fail` fails. The defaults pass a re-bake on another toolchain (float rounding moves
// vertices by micrometres) and fail a change a player could see.
struct DiffTolerances {
  struct Pair {
    double warn, fail;
  };
  Pair animationMm{0.01, 0.1};      // vertex displacement after skinning, any time of any clip
  Pair weight{1e-6, 1e-4};          // skin weights (the influences themselves must be the same)
  Pair positionMm{0.01, 0.1};       // bind-pose positions; inverse bind translations
  Pair normalDeg{0.01, 0.1};        // bind-pose normals
  Pair uv{1e-6, 1e-4};              // texture coordinates
  Pair lodError{1e-4, 1e-2};        // collapse error curve, relative to its largest value
  Pair clothMm{0.01, 0.1};          // cloth loop positions
  Pair texel{1.0 / 255, 4.0 / 255}; // atlases and the diffuse texture, per channel in 0..1
  Pair texelRelative{0.0, 0.0};     // and relative to the mean of the two (idiff's -failrelative)
  Pair texelPercent{0.0, 0.1};      // percent of texels past both fail tolerances (-failpercent)
};
// Reads {"animation_mm": {"warn": W, "fail": F}, ...}: only the keys given change. Throws
// Error on an unknown key, a warn over its fail, or a negative value.
DiffTolerances tolerancesFromJson(const nlohmann::json &j, const std::string &context);
nlohmann::ordered_json tolerancesJson(const DiffTolerances &t);

// Also crowdbake diff's exit code: the pack passes (identical or within `warn`), is within
// `fail`, fails, or holds different things (a chunk only in one, other joints, vertex counts).
enum class DiffVerdict { Pass = 0, Warn = 1, Fail = 2, Incomparable = 3 };
const char *name(DiffVerdict v);

struct DiffItem {
  std::string chunk; // "ANIM", "IMPO walk/dress", ...
  std::string what;  // "animation displacement", "provenance", ...
  double value = 0;  // the largest change, in `unit`
  std::string unit;  // "mm", "deg", "", ...
  std::string worst; // where: "clip 'run', t 0.517 s, vertex 123 (joint 'forearm_l')"
  DiffVerdict verdict = DiffVerdict::Pass;
  bool identical = false;     // byte-identical payloads
  bool informational = false; // listed, never failing (provenance)
};

struct PackDiff {
  std::vector<DiffItem> items;
  DiffVerdict verdict = DiffVerdict::Pass; // the worst item's (informational ones aside)
  double mmPerUnit = 0; // the golden's model units in mm at a 1.8 m character (0: no mesh)
};

PackDiff diffPacks(const pack::Reader &golden, const pack::Reader &fresh,
                   const DiffTolerances &tolerances);
nlohmann::ordered_json diffJson(const PackDiff &d, const DiffTolerances &t);

} // namespace crowd
