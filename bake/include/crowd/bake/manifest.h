// Character manifests and libraries for crowdbake build (JSON written by users). A character is
// a body, its outfits, the clips to keep and the settings of each bake; a library lists
// characters (manifest files relative to it, or inline objects). Every default lives in the
// bakes' option structs; a manifest only overrides. Errors say "FILE:LINE:COLUMN: /key: what".
#pragma once
#include "crowd/bake/input_files.h"
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "crowd/bake/anim_bake.h"
#include "crowd/bake/cloth_bake.h"
#include "crowd/bake/impostor_bake.h"
#include "crowd/bake/job_limits.h"
#include "crowd/bake/lod_bake.h"
#include "crowd/bake/outfit_bake.h"
#include "crowd/bake/terrain_bake.h"

namespace crowd {

// A looped garment ("cloth": [...]): a cache of one garment of an outfit over one clip.
struct ClothEntry {
  std::string outfit, garment, clip;
  std::string cache; // PC2 or MDD path, resolved against the manifest's folder
  ClothBakeOptions options;
  nlohmann::ordered_json canonical() const; // settings, no path
};

struct CharacterManifest {
  std::string name;   // names the output pack (NAME.crowdpack in a library build)
  std::string source; // the file it came from (a library for inline manifests)
  size_t entry = 0;   // its place in the library's "characters" (0 for a character manifest)
  std::string body;   // glTF path, resolved against the manifest's folder
  std::vector<std::pair<std::string, std::string>> outfits; // name, glTF path (manifest order)
  std::vector<std::string> clips;                           // clips to keep; empty: every clip
  std::string mesh;  // the body's mesh to bake (ImportOptions::mesh)
  InputPolicy input; // how its glTFs' own files are confined (not a setting)
  AnimBakeOptions anim;
  bool lod = true; // continuous LOD on every sub-mesh ("lod": false turns it off)
  LodOptions lodOptions;
  OutfitOptions outfitOptions; // "visibility": how outfits hide body parts
  // The (clip, outfit) pairs to bake impostors of: every pair of the manifest's "impostor"
  // clips and outfits (a scene build keeps those it draws far away). An outfit of "" is the bare
  // body, a clip of "" the first.
  std::vector<std::pair<std::string, std::string>> impostorPairs;
  ImpostorOptions impostor;
  std::vector<ClothEntry> cloth; // each (outfit, garment, clip) at most once
  // Set for an environment (crowdbake terrain): `body` is the environment's glTF and its one
  // job is the terrain bake.
  std::optional<TerrainOptions> terrain;
  // "limits": this character's jobs' bounds, over the build's --job-max-* (never in a key).
  JobLimits limits;
  // Settings in a fixed order, for provenance and cache keys (no paths: they move).
  nlohmann::ordered_json canonical() const;
};

struct Library {
  std::string path;
  bool single = false; // the file was one character manifest, not a library
  std::vector<CharacterManifest> characters;
};

// A character manifest ({"name", "body", ...}) or a library ({"characters": [...]}).
Library loadLibrary(const std::string &path, const InputPolicy &policy = {});
// Only the character of entry `entry` (a build's job process: one character, not a library).
Library loadLibrary(const std::string &path, const InputPolicy &policy, size_t entry);
// One manifest from its text (tests); `path` names it in errors and anchors relative paths.
CharacterManifest parseManifest(const std::string &text, const std::string &path,
                                const InputPolicy &policy = {});

} // namespace crowd
