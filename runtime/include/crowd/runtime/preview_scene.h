// The scene crowdplay shows for a pack given without a scene file: one instance of every
// (clip, outfit) pair in a row facing the camera, framed by the pack's bounding sphere, and the
// same row far behind, past the distance where impostors take over; the camera turns around the
// row (a turntable, starting in front). A choice narrows the row to one clip, outfit or pair.
#pragma once
#include <string>

#include "crowd/formats/character_pack.h"
#include "crowd/runtime/scene.h"

namespace crowd::runtime {

struct PreviewChoice {
  int clip = -1, outfit = -1; // indices into the pack's clips and outfits; -1: every one
};

// Throws crowd::Error when a chosen index is outside the pack's clips or outfits.
Scene previewScene(const std::string &packPath, const pack::CharacterPack &pack,
                   const PreviewChoice &choice = {});

// How long the preview's clip key crossfades.
constexpr double kClipKeyFadeSeconds = 0.3;

// Starts `next` (the preview of `chosen`) in a crossfade from `previous`'s clip at scene time
// `now`, when both show one clip (then the row is the same instances); otherwise leaves it.
void crossfadeFrom(Scene &next, const PreviewChoice &previous, const PreviewChoice &chosen,
                   double now, double seconds = kClipKeyFadeSeconds);

} // namespace crowd::runtime
