// The figures each bake reports besides animation (anim_report.h): a job's part figures, so the
// same keys reach every --report and the build report.
#pragma once
#include <cstddef>
#include <vector>

#include <nlohmann/json.hpp>

#include "crowd/bake/cloth_bake.h"
#include "crowd/bake/impostor_bake.h"
#include "crowd/bake/outfit_bake.h"
#include "crowd/formats/chunks.h"

namespace crowd {

// Continuous LOD: triangles in and stored, the floor and the fewest vertices that keep 50%, 25%,
// 10% and 5% of the triangles, with their quadric error.
// `colourChange` (optional, LodResult::colourChange): each level's largest colour change from
// closed hard edges, 8-bit RGB, beside its quadric error.
nlohmann::ordered_json lodFigures(const pack::Lod &lod, size_t inputTriangles,
                                  const std::vector<float> *colourChange = nullptr);

// Outfits: per outfit its garments, hidden and removed body faces and each body sub-mesh's
// coverage; faces stored by the naive, pre-fitted and tagged methods (and extrapolated to 10
// outfits, the seed's figure 6); the hole check when it ran.
nlohmann::ordered_json outfitFigures(const OutfitBakeResult &r, const OutfitOptions &options);

// An impostor: atlas size, occupancy, bytes per frame (and uncropped), mirror IoU.
nlohmann::ordered_json impostorFigures(const ImpostorBakeResult &r, const ImpostorOptions &options);
// Its accuracy against the true render (ImpostorOptions::measure).
nlohmann::ordered_json impostorAccuracyFigures(const ImpostorAccuracy &a);

// A cloth loop: the chosen loop, every candidate's pass-1 and pass-2 scores (so a reader sees
// when pass 2 changed the choice), the verdict, the blend and push-out, the stored bytes and the
// quantisation error in millimetres at 1.8 m.
nlohmann::ordered_json clothFigures(const ClothBakeResult &r);

} // namespace crowd
