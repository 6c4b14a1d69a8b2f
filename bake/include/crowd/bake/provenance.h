// Provenance of a bake: baker version, settings and a content hash of every input file.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "crowd/formats/chunks.h"

namespace crowd {

inline constexpr const char *kBakerVersion = "crowdbake 0.1.0";

// Inputs are recorded by file name (not full path) so the same files baked from another
// directory give identical bytes.
pack::Provenance makeProvenance(const std::vector<std::string> &inputs,
                                std::vector<std::pair<std::string, std::string>> settings);

} // namespace crowd
