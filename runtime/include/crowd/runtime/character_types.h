// Character types for the renderer. The renderer draws one impostor per character type, while a
// character pack may hold impostors for several (clip, outfit) pairs: each pair becomes a type of
// its own, sharing the pack, and the instances that play that clip in that outfit move to it.
#pragma once
#include <string>
#include <vector>

#include "crowd/formats/character_pack.h"
#include "crowd/runtime/cloth_playback.h"
#include "crowd/runtime/scene.h"

namespace crowd::runtime {

struct CharacterTypes {
  std::vector<const pack::AnimationPack *> packs; // per type
  std::vector<const pack::Impostor *> impostors;  // per type, null for none
  std::vector<ClothLoops> cloths;                 // per type: its pack's cloth loops
};

// `sceneImpostors[k]` (null for none) is an impostor the scene names for pack k; it replaces the
// pack's own. Rewrites scene.instances[*].pack and scene.packNames to the types. The packs must
// outlive the result.
CharacterTypes characterTypes(Scene &scene, const std::vector<pack::CharacterPack> &packs,
                              const std::vector<const pack::Impostor *> &sceneImpostors);

} // namespace crowd::runtime
