// Test helpers: the sample humanoid, generated, imported and baked once per test program.
#pragma once
#include "crowd/bake/character.h"
#include "crowd/bake/outfit_bake.h"
#include "crowd/formats/chunks.h"

namespace crowd::test {

const Character &sampleHumanoid();
// The three sample outfits: dress, jumper_skirt, shirt_trousers.
std::vector<OutfitInput> sampleOutfits();
// The sample humanoid baked with LOD (default options), read back through the pack reader.
const pack::AnimationPack &sampleHumanoidLodPack();

} // namespace crowd::test
