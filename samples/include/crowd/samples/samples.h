// Deterministic sample characters: a procedural humanoid (22 joints, body in sub-meshes by
// region, UV seams, a diffuse texture, walk/run/idle clips) and three pre-fitted outfits on the
// same skeleton, each written as a glTF binary through tinygltf.
#pragma once
#include <string>
#include <vector>

namespace crowd::samples {

// File names later bakes and scripts rely on.
inline const std::vector<std::string> kFiles = {
    "humanoid.glb", "outfit_dress.glb", "outfit_jumper_skirt.glb", "outfit_shirt_trousers.glb"};

// The sample environment for the terrain bake (village.h): ground, steps, buildings, a square;
// writeSamples also writes its agents' images, village_behaviour.png and village_callbacks.png.
inline const std::string kVillageFile = "village.glb";

// Writes every sample into `dir` (created if missing); throws crowd::Error on failure.
void writeSamples(const std::string &dir);

} // namespace crowd::samples
