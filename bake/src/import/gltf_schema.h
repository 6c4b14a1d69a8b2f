// The checks of the glTF JSON that tinygltf leaves out (it reads a mistyped or dangling index as
// "absent" and goes on): every index property is a non-negative integer naming an element that
// exists, every enumerated string is a string, each animation channel has a target path, and
// every required extension is one the importer reads.
// Errors name the file and the JSON pointer: "FILE: /nodes/3/mesh: ...".
#pragma once
#include <set>
#include <string>
#include <string_view>

namespace crowd {

// Extensions a file may require: those that change nothing the bakes read, or that the importer
// covers (the accessor reader quantization, base_colour_uv.h the texture transform, the diffuse
// texture's reader a WebP image, meshopt_views.h compressed buffer views). Any other in
// "extensionsRequired" is an error, checked here.
inline const std::set<std::string> kSupportedRequired = {
    "KHR_mesh_quantization",  "KHR_texture_transform", "KHR_materials_emissive_strength",
    "KHR_materials_unlit",    "EXT_texture_webp",      "EXT_meshopt_compression",
    "KHR_meshopt_compression"};

void checkGltfJson(std::string_view json, const std::string &path);

// A URI as tinygltf reads it: percent-decoded, "./" dropped.
std::string uriAsRead(const std::string &uri);

} // namespace crowd
