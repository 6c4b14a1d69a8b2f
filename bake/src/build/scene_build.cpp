#include "crowd/bake/scene_build.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include <glm/glm.hpp>

#include "crowd/bake/evaluate.h"
#include "crowd/bake/import.h"
#include "crowd/formats/error.h"
#include "crowd/formats/limits.h"
#include "crowd/runtime/lod_select.h"
#include "crowd/runtime/scene.h"

namespace crowd {

namespace {

using nlohmann::ordered_json;
using Pair = std::pair<std::string, std::string>; // clip, outfit

// Eye positions the scene's camera takes: its fixed position, or its path sampled finely
// enough that no instance's nearest and farthest approach is missed by more than a little.
std::vector<glm::dvec3> eyes(const runtime::Camera &camera) {
  std::vector<glm::dvec3> out;
  glm::dvec3 eye, look;
  if (camera.path.size() < 2) {
    camera.at(0, eye, look);
    return {eye};
  }
  const double t0 = camera.path.front().time, t1 = camera.path.back().time;
  const int samples = 64 * int(camera.path.size());
  for (int k = 0; k <= samples; ++k) {
    camera.at(t0 + (t1 - t0) * k / samples, eye, look);
    out.push_back(eye);
  }
  return out;
}

// The character at rest, as the bakes see it: centre and radius of its skinned rest pose.
struct RestSphere {
  glm::dvec3 centre{0};
  double radius = 0;
  std::vector<std::string> clips; // the clips it keeps, in order
};

RestSphere restSphere(const CharacterManifest &m, const InputPolicy &policy) {
  ImportOptions io;
  io.input = policy;
  io.mesh = m.mesh;
  Reporter quiet;
  quiet.quiet = true;
  const Character c = importGltf(m.body, io, quiet);
  RestSphere s;
  const auto positions = posedPositions(c, nullptr, 0);
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (const auto &p : positions)
    lo = glm::min(lo, p), hi = glm::max(hi, p);
  s.centre = (lo + hi) * 0.5;
  for (const auto &p : positions)
    s.radius = std::max(s.radius, glm::length(p - s.centre));
  for (const auto &clip : c.clips)
    if (m.clips.empty() || std::find(m.clips.begin(), m.clips.end(), clip.name) != m.clips.end())
      s.clips.push_back(clip.name);
  if (!m.clips.empty()) // the manifest's order
    s.clips = m.clips;
  return s;
}

std::string listed(const std::vector<std::string> &names) {
  std::string out;
  for (const auto &n : names)
    out.append(out.empty() ? "" : ", ").append(n.empty() ? "\"\"" : n);
  return out.empty() ? "none" : out;
}

template <class T> bool contains(const std::vector<T> &v, const T &x) {
  return std::find(v.begin(), v.end(), x) != v.end();
}

// What the scene's instances of character m (scene pack `pack`) play and wear, and how far each
// (clip, outfit) pair gets from the camera's eyes.
struct Drawn {
  std::vector<std::string> clips, outfits;
  std::map<Pair, double> farthest; // per pair drawn, the farthest any instance gets
};
Drawn whatTheSceneDraws(const runtime::Scene &scene, size_t pack, const CharacterManifest &m,
                        const RestSphere &rest, const std::vector<glm::dvec3> &eyePositions,
                        const std::string &ctx) {
  Drawn d;
  auto &clips = d.clips;
  auto &outfits = d.outfits;
  auto &farthest = d.farthest;
  std::vector<std::string> outfitNames;
  for (const auto &[name, file] : m.outfits)
    outfitNames.push_back(name);
  for (const auto &inst : scene.instances) {
    if (inst.pack != pack)
      continue;
    std::string clip = scene.clipNames.empty() ? "" : scene.clipNames[inst.clip];
    if (clip.empty() && !rest.clips.empty())
      clip = rest.clips.front(); // "": the first clip
    if (!clip.empty() && !contains(rest.clips, clip))
      throw Error(ctx + " has no clip '" + clip + "' (clips: " + listed(rest.clips) + ")");
    std::string outfit = scene.outfitNames[inst.outfit];
    if (outfit.empty() && !outfitNames.empty())
      outfit = outfitNames.front(); // "": the first outfit
    if (!outfit.empty() && !contains(outfitNames, outfit))
      throw Error(ctx + " has no outfit '" + outfit + "' (outfits: " + listed(outfitNames) + ")");
    if (!contains(clips, clip))
      clips.push_back(clip);
    if (!outfit.empty() && !contains(outfits, outfit))
      outfits.push_back(outfit);
    const glm::dvec3 centre =
        inst.position +
        glm::dvec3(std::cos(inst.yaw) * rest.centre.x + std::sin(inst.yaw) * rest.centre.z,
                   rest.centre.y,
                   -std::sin(inst.yaw) * rest.centre.x + std::cos(inst.yaw) * rest.centre.z);
    double far = 0;
    for (const auto &eye : eyePositions)
      far = std::max(far, glm::length(eye - centre));
    double &f = farthest[{clip, outfit}];
    f = std::max(f, far);
  }
  return d;
}

// The manifest's impostor pairs kept: those an instance takes past the switch distance (with the
// player's hysteresis); the rest, and pairs drawn far that the manifest does not list, said in
// `cj`.
std::vector<Pair> impostorsNeeded(const CharacterManifest &m, const RestSphere &rest,
                                  const Drawn &drawnPairs, const runtime::Scene &scene,
                                  const SceneBuildOptions &o, ordered_json &cj) {
  const auto &farthest = drawnPairs.farthest;
  // The player goes over to an impostor this much past its switch distance (hysteresis).
  const double farFactor = 1 + runtime::kImpostorHysteresis;
  const double fovY = glm::radians(scene.camera.fovYDegrees);
  const double switchAt = o.switchDistance > 0 ? o.switchDistance
                                               : 2 * rest.radius / m.impostor.texels *
                                                     o.screenHeight / (2 * std::tan(fovY / 2));
  std::vector<std::pair<std::string, std::string>> pairs;
  for (const auto &listedPair : m.impostorPairs) { // kept as listed: the same job key
    const std::string &outfit = listedPair.second;
    std::string clip = listedPair.first;
    if (clip.empty() && !rest.clips.empty())
      clip = rest.clips.front();
    ordered_json pj{{"clip", clip}, {"outfit", outfit}};
    const auto drawn = farthest.find({clip, outfit});
    if (drawn == farthest.end()) {
      pj["why"] = "no instance plays this clip in this outfit";
    } else if (drawn->second <= switchAt * farFactor) {
      pj["why"] = "no instance gets past the switch distance (the farthest: " +
                  std::to_string(drawn->second) + ")";
    } else {
      pairs.push_back(listedPair);
      cj["impostors"].push_back({{"clip", clip}, {"outfit", outfit}});
      continue;
    }
    cj["impostors_left_out"].push_back(pj);
  }
  auto listedInManifest = [&](const Pair &p) {
    return contains(m.impostorPairs, p) || (!rest.clips.empty() && p.first == rest.clips.front() &&
                                            contains(m.impostorPairs, Pair{"", p.second}));
  };
  for (const auto &[pair, far] : farthest)
    if (far > switchAt * farFactor && !listedInManifest(pair))
      cj["drawn_far_without_an_impostor"].push_back(
          {{"clip", pair.first}, {"outfit", pair.second}, {"why", "the manifest lists none"}});
  cj["switch_distance"] = switchAt;
  return pairs;
}

} // namespace

void SceneBuildOptions::validate() const {
  if (screenHeight < 16 || screenHeight > limits::kScreenSide)
    throw Error("screen: must be in [16, " + std::to_string(limits::kScreenSide) + "] pixels");
  if (!(switchDistance >= 0) || !std::isfinite(switchDistance))
    throw Error("switch distance: must be a finite number >= 0");
}

ordered_json narrowToScene(Library &library, const SceneBuildOptions &o,
                           const InputPolicy &policy) {
  o.validate();
  const runtime::Scene scene = runtime::loadScene(o.scene);
  const auto eyePositions = eyes(scene.camera);

  ordered_json report;
  report["file"] = o.scene;
  report["instances"] = scene.instances.size();
  report["screen_height"] = o.screenHeight;
  report["fov"] = scene.camera.fovYDegrees;
  std::map<std::string, size_t> packOf; // character name -> scene pack index
  for (size_t p = 0; p < scene.packPaths.size(); ++p) {
    const std::string stem = std::filesystem::path(scene.packPaths[p]).stem().string();
    const bool known = std::any_of(library.characters.begin(), library.characters.end(),
                                   [&](const auto &m) { return m.name == stem; });
    if (known)
      packOf[stem] = p;
    else
      report["scene_packs_not_in_library"].push_back(scene.packPaths[p]);
  }
  if (packOf.empty())
    throw Error(o.scene + ": draws none of the library's characters (a scene pack "
                          "'.../NAME.crowdpack' names the character NAME)");

  std::vector<CharacterManifest> kept;
  for (CharacterManifest &m : library.characters) {
    ordered_json cj{{"name", m.name}};
    auto it = packOf.find(m.name);
    if (it == packOf.end()) {
      cj["left_out"] = "the scene draws no instance of it";
      report["characters"].push_back(cj);
      continue;
    }
    const RestSphere rest = restSphere(m, policy);
    const std::string ctx = o.scene + ": character '" + m.name + "'";
    const Drawn drawn = whatTheSceneDraws(scene, it->second, m, rest, eyePositions, ctx);
    const auto &clips = drawn.clips, &outfits = drawn.outfits;
    if (clips.empty()) {
      cj["left_out"] = "the scene lists its pack, but no instance uses it";
      report["characters"].push_back(cj);
      continue;
    }
    // Keep the manifest's order, so that "" stays the first clip and outfit.
    std::vector<std::string> keptClips, droppedClips;
    for (const auto &c : rest.clips)
      (contains(clips, c) ? keptClips : droppedClips).push_back(c);
    std::vector<std::pair<std::string, std::string>> keptOutfits;
    std::vector<std::string> droppedOutfits;
    for (const auto &of : m.outfits)
      if (contains(outfits, of.first))
        keptOutfits.push_back(of);
      else
        droppedOutfits.push_back(of.first);
    cj["clips"] = keptClips;
    if (!droppedClips.empty())
      cj["clips_left_out"] = {{"names", droppedClips}, {"why", "no instance plays them"}};
    if (!m.outfits.empty())
      cj["outfits"] = ordered_json::array();
    for (const auto &of : keptOutfits)
      cj["outfits"].push_back(of.first);
    if (!droppedOutfits.empty())
      cj["outfits_left_out"] = {{"names", droppedOutfits}, {"why", "no instance wears them"}};

    const std::vector<Pair> pairs = impostorsNeeded(m, rest, drawn, scene, o, cj);
    cj["rest_radius"] = rest.radius;
    // Only what changes is narrowed: a character the scene draws whole keeps its job keys,
    // and with them what a full build left in the cache.
    if (!droppedClips.empty())
      m.clips = keptClips;
    m.outfits = keptOutfits;
    m.impostorPairs = pairs;
    if (o.switchDistance > 0) {
      m.impostor.switchDistance = o.switchDistance;
      m.impostor.screenHeight = o.screenHeight;
      m.impostor.fovDegrees = scene.camera.fovYDegrees;
      m.impostor.validate();
    }
    kept.push_back(m);
    report["characters"].push_back(cj);
  }
  library.characters = std::move(kept);
  return report;
}

} // namespace crowd
