// The checks of the glTF JSON that tinygltf leaves out (it reads a mistyped or dangling index as
// "absent" and goes on): every index property is a non-negative integer naming an element that
// exists, every enumerated string is a string, and each animation channel has a target path.
// Errors name the file and the JSON pointer: "FILE: /nodes/3/mesh: ...".
#pragma once
#include <string>
#include <string_view>

namespace crowd {

void checkGltfJson(std::string_view json, const std::string &path);

} // namespace crowd
