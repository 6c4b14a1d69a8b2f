// Test helpers: the sample humanoid, generated, imported and baked once per test program.
#pragma once
#include "crowd/bake/character.h"
#include "crowd/formats/chunks.h"

namespace crowd::test {

const Character &sampleHumanoid();
// The sample humanoid baked with LOD (default options), read back through the pack reader.
const pack::AnimationPack &sampleHumanoidLodPack();

} // namespace crowd::test
