// The scene crowdplay shows for a pack given without a scene file: one instance of every
// (clip, outfit) pair in a row facing the camera, framed by the pack's bounding sphere, and the
// same row far behind, past the distance where impostors take over.
#pragma once
#include <string>

#include "crowd/formats/character_pack.h"
#include "crowd/runtime/scene.h"

namespace crowd::runtime {

Scene previewScene(const std::string &packPath, const pack::CharacterPack &pack);

} // namespace crowd::runtime
