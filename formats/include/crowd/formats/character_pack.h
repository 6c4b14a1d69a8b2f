// A character pack (crowdbake build): one file with everything the player draws of a character:
// the animation pack's chunks (skeleton, clips, textures, mesh, continuous LOD, outfits) and one
// impostor chunk per baked (clip, outfit) pair and one cloth-loop chunk per looped (outfit,
// garment, clip). Plain animation packs load as character packs
// without impostors.
#pragma once
#include <string>
#include <vector>

#include "crowd/formats/chunks.h"
#include "crowd/formats/cloth.h"
#include "crowd/formats/impostor.h"

namespace crowd::pack {

struct CharacterPack {
  AnimationPack body;              // provenance, skeleton, clips, textures, mesh, LOD, outfits
  std::vector<Impostor> impostors; // in chunk order; each (clip, outfit) at most once
  std::vector<ClothLoop> cloths;   // in chunk order; each (outfit, garment, clip) at most once
  // The impostor of (clip, outfit), or null. An outfit of "" matches an impostor of the bare body.
  const Impostor *impostor(const std::string &clip, const std::string &outfit) const;
};

// Decodes every chunk and cross-checks the impostors and cloth loops against the body: their
// clips and outfits exist, none is repeated.
CharacterPack loadCharacterPack(const Reader &reader);
std::vector<uint8_t> packBytes(const CharacterPack &pack);

} // namespace crowd::pack
