// crowdbake build --scene: a library narrowed to what one scene draws. A scene pack
// (".../NAME.crowdpack") names the library character NAME; a character keeps only the clips and
// outfits its instances use, and impostors only for the listed (clip, outfit) pairs that some
// instance shows past the switch distance, with texels chosen so that one texel covers one pixel
// there. What was left out, and why, goes into the build report.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

#include "crowd/bake/input_files.h"
#include "crowd/bake/manifest.h"

namespace crowd {

struct SceneBuildOptions {
  std::string scene;       // SCENE.json (crowdplay's scene file); empty: a full build
  int screenHeight = 1080; // pixels: the height of the viewport the scene is drawn at
  // Scene units from the camera; 0: per character, the distance where its manifest's impostor
  // texels cover one pixel each (so the manifest's resolution is kept).
  double switchDistance = 0;
  void validate() const; // throws crowd::Error naming the field
};

// Narrows `library` to what the scene draws and returns the report's account of it: per
// character what was kept, what was left out and why. Throws crowd::Error when the scene draws
// no character of the library, or uses a clip or outfit a character does not have.
nlohmann::ordered_json narrowToScene(Library &library, const SceneBuildOptions &options,
                                     const InputPolicy &policy);

} // namespace crowd
