// How a build's input policy and scene options travel to other processes (a job's spec, a Slurm
// plan): one writer and one reader, so that a new option is carried everywhere by adding it here.
#pragma once

#include "crowd/bake/input_files.h"
#include "crowd/bake/scene_build.h"

namespace crowd {

template <class Json>
void writeBuildInputs(Json &j, const InputPolicy &files, const SceneBuildOptions &scene) {
  j["asset_root"] = files.assetRoot;
  j["max_file_bytes"] = files.maxFileBytes;
  j["scene"] = scene.scene;
  j["screen_height"] = scene.screenHeight;
  j["switch_distance"] = scene.switchDistance;
}

// Throws what Json::at throws for a missing or mistyped field; the caller names the file.
template <class Json>
void readBuildInputs(const Json &j, InputPolicy &files, SceneBuildOptions &scene) {
  files.assetRoot = j.at("asset_root");
  files.maxFileBytes = j.at("max_file_bytes");
  scene.scene = j.at("scene");
  scene.screenHeight = j.at("screen_height");
  scene.switchDistance = j.at("switch_distance");
}

} // namespace crowd
