// Provenance of a bake: baker version, settings and a content hash of every input file.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "crowd/formats/chunks.h"

namespace crowd {

inline constexpr const char *kBakerVersion = "crowdbake 0.1.0";


} // namespace crowd
