// glTF 2.0 import (tinygltf): .glb/.gltf with external or data-URI buffers into a Character.
// Bad input throws crowd::Error naming file and place; repairable oddities are fixed and
// reported through the Reporter with counts.
#pragma once
#include <string>
#include <vector>

#include "crowd/bake/character.h"
#include "crowd/bake/input_files.h"
#include "crowd/bake/report.h"

namespace crowd {

struct ImportOptions {
  // Mesh to bake, by name. Empty: every skinned mesh with every skin it uses, merged into one
  // skeleton, plus meshes rigidly parented to its joints (or, without skins, every mesh as a
  // rigid part).
  std::string mesh;
  // Where external buffers and images may resolve, and how large an input may be.
  InputPolicy input;
};

Character importGltf(const std::string &path, const ImportOptions &options, Reporter &reporter);

// The glTF and the external files it names (buffer and image URIs, resolved under the policy),
// the files whose bytes its import reads: what a bake's cache key and provenance hash. A file
// that cannot be read or resolved is left out (with the files after it), for the import to
// report.
std::vector<std::string> gltfFiles(const std::string &path, const InputPolicy &policy);

} // namespace crowd
