// Provenance of a bake: baker version, settings and a content hash of every input file.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "crowd/formats/chunks.h"
#include "crowd/formats/version.h"

namespace crowd {

// In every cache key and pack: raise the project's VERSION (top-level CMakeLists.txt) whenever a
// bake's output changes for the same inputs and settings, or a build would take the older baker's
// parts from its cache. Each raise and why: CHANGELOG.md.
inline constexpr const char *kBakerVersion = "crowdbake " CROWD_VERSION;

// The compiler and C library this crowdbake was built with and runs on: floats may round
// differently under another, so byte-identical goldens hold only on the same toolchain
// (tests/golden/toolchain.txt; elsewhere they are checked with crowdbake diff's tolerances).
std::string toolchain();

} // namespace crowd
