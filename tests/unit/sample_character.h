// Test helper: the sample humanoid, generated and imported once per test program.
#pragma once
#include "crowd/bake/character.h"

namespace crowd::test {

const Character &sampleHumanoid();

} // namespace crowd::test
