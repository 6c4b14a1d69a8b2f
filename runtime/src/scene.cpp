#include "crowd/runtime/scene.h"

#include <cmath>
#include <filesystem>
#include <functional>
#include <random>

#include <nlohmann/json.hpp>

#include "crowd/formats/error.h"
#include "crowd/formats/file_read.h"
#include "crowd/formats/limits.h"
#include "crowd/support/json_checker.h"

namespace crowd::runtime {
namespace {

using nlohmann::json;

// The scene's own value shapes on top of the shared checks.
class Checker : public support::JsonChecker {
public:
  using support::JsonChecker::JsonChecker;

  glm::dvec3 vec3(const json &j, const std::vector<std::string> &keys) const {
    if (!j.is_array() || j.size() != 3)
      fail(keys, "expected [x, y, z]");
    glm::dvec3 v;
    for (int k = 0; k < 3; ++k)
      v[k] = number(j[size_t(k)], keys, -1e6, 1e6);
    return v;
  }

  // A number, or {"min": a, "max": b} drawn uniformly.
  double sample(const json &j, const std::vector<std::string> &keys, std::mt19937_64 &rng,
                double lo, double hi) const {
    if (j.is_object()) {
      for (auto it = j.begin(); it != j.end(); ++it)
        if (it.key() != "min" && it.key() != "max")
          fail(keys, "unknown key '" + it.key() + "'");
      double a = number(j.value("min", json(0.0)), keys, lo, hi);
      double b = number(j.value("max", json(a)), keys, lo, hi);
      if (b < a)
        fail(keys, "max is below min");
      return a + (b - a) * std::uniform_real_distribution<double>(0, 1)(rng);
    }
    return number(j, keys, lo, hi);
  }

  // A name, a list of names (picked uniformly) or {name: weight, ...}.
  void choices(const json &j, const std::vector<std::string> &keys, const std::string &what,
               std::vector<std::string> &names, std::vector<double> &weights) const {
    names.clear();
    weights.clear();
    if (j.is_string()) {
      names = {j.get<std::string>()};
    } else if (j.is_array() && !j.empty() &&
               std::all_of(j.begin(), j.end(), [](auto &x) { return x.is_string(); })) {
      names = j.get<std::vector<std::string>>();
    } else if (j.is_object() && !j.empty()) {
      for (auto it = j.begin(); it != j.end(); ++it) {
        names.push_back(it.key());
        weights.push_back(number(it.value(), keys, 0, 1e9));
      }
      if (std::all_of(weights.begin(), weights.end(), [](double w) { return w == 0; }))
        fail(keys, "the weights are all zero");
    } else {
      fail(keys, "expected a " + what + " name, a list of names or {name: weight, ...}");
    }
    weights.resize(names.size(), 1.0);
  }
};

// Equal weights pick uniformly, as scenes did before weights were allowed (same instances).
size_t pick(const std::vector<double> &weights, std::mt19937_64 &rng) {
  if (std::adjacent_find(weights.begin(), weights.end(), std::not_equal_to<>()) == weights.end())
    return std::uniform_int_distribution<size_t>(0, weights.size() - 1)(rng);
  return std::discrete_distribution<size_t>(weights.begin(), weights.end())(rng);
}

} // namespace

void Camera::at(double t, glm::dvec3 &eye, glm::dvec3 &look) const {
  eye = position;
  look = target;
  if (path.empty())
    return;
  double end = path.back().time;
  if (loopPath && end > 0)
    t = t - end * std::floor(t / end);
  if (t <= path.front().time || path.size() == 1) {
    eye = path.front().position, look = path.front().target;
    return;
  }
  for (size_t k = 1; k < path.size(); ++k)
    if (t <= path[k].time) {
      double a = (t - path[k - 1].time) / (path[k].time - path[k - 1].time);
      eye = glm::mix(path[k - 1].position, path[k].position, a);
      look = glm::mix(path[k - 1].target, path[k].target, a);
      return;
    }
  eye = path.back().position, look = path.back().target;
}

namespace {

uint64_t worldAgents(const WorldSettings &w) {
  uint64_t n = 0;
  for (const auto &a : w.spawn)
    n += a.count;
  return std::max<uint64_t>(n, 1);
}

// "world": {"terrain", "behaviour", "callbacks": {"image", "bus_stops": [{"colour", "every"}]},
// "attractors": [[x, z]...], "spawn": [{"min": [x, z], "max": [x, z], "count"}...],
// "clips": {"idle", "walk", "run"}, "fade", "seed", "walk_speed", "run_speed", "runners"}.
// The clips' names become the scene's clip names.
void parseWorld(const Checker &c, const json &w, const std::filesystem::path &dir, Scene &s) {
  WorldSettings &out = s.world;
  const std::vector<std::string> at = {"world"};
  c.onlyKeys(w, at,
             {"terrain", "behaviour", "callbacks", "attractors", "spawn", "clips", "fade", "seed",
              "walk_speed", "run_speed", "runners"});
  auto file = [&](const char *key) {
    if (!w.contains(key))
      return std::string();
    if (!w[key].is_string())
      c.fail({"world", key}, "expected a file path");
    return (dir / w[key].get<std::string>()).lexically_normal().string();
  };
  out.terrainPath = file("terrain");
  if (out.terrainPath.empty())
    c.fail(at, "expected \"terrain\": a pack from crowdbake terrain");
  out.behaviourPath = file("behaviour");
  auto xz = [&](const json &p, const std::vector<std::string> &keys) {
    if (!p.is_array() || p.size() != 2)
      c.fail(keys, "expected [x, z]");
    return glm::vec2(float(c.number(p[0], keys, -1e6, 1e6)),
                     float(c.number(p[1], keys, -1e6, 1e6)));
  };
  if (w.contains("callbacks")) {
    const json &cb = w["callbacks"];
    c.onlyKeys(cb, {"world", "callbacks"}, {"image", "bus_stops"});
    if (!cb.contains("image") || !cb["image"].is_string())
      c.fail({"world", "callbacks", "image"}, "expected the callback image's path");
    out.callbackPath = (dir / cb["image"].get<std::string>()).lexically_normal().string();
    for (const auto &stop : cb.value("bus_stops", json::array())) {
      const std::vector<std::string> keys = {"world", "callbacks", "bus_stops"};
      c.onlyKeys(stop, keys, {"colour", "every"});
      WorldSettings::BusStop b;
      const glm::dvec3 colour = c.vec3(stop.value("colour", json::array({0, 0, 255})), keys);
      for (int k = 0; k < 3; ++k) {
        if (colour[k] < 0 || colour[k] > 255 || colour[k] != std::floor(colour[k]))
          c.fail(keys, "colour components are whole numbers 0 to 255");
        b.colour[k] = uint8_t(colour[k]);
      }
      b.every = c.number(stop.value("every", json(20)), keys, 0.01, 1e6);
      out.busStops.push_back(b);
    }
  }
  for (const auto &p : w.value("attractors", json::array()))
    out.attractors.push_back(xz(p, {"world", "attractors"}));
  if (!w.contains("spawn") || !w["spawn"].is_array() || w["spawn"].empty())
    c.fail({"world", "spawn"}, "expected [{\"min\": [x, z], \"max\": [x, z], \"count\": n}]");
  for (const auto &a : w["spawn"]) {
    const std::vector<std::string> keys = {"world", "spawn"};
    c.onlyKeys(a, keys, {"min", "max", "count"});
    SpawnArea area;
    area.min = xz(a.value("min", json::array({0, 0})), keys);
    area.max = xz(a.value("max", json::array({0, 0})), keys);
    area.count = uint32_t(c.number(a.value("count", json(1)), keys, 0, double(limits::kInstances)));
    out.spawn.push_back(area);
  }
  const json clips = w.value("clips", json{{"idle", "idle"}, {"walk", "walk"}, {"run", "run"}});
  c.onlyKeys(clips, {"world", "clips"}, {"idle", "walk", "run"});
  s.clipNames.clear();
  for (const char *pace : {"idle", "walk", "run"}) {
    if (!clips.contains(pace) || !clips[pace].is_string())
      c.fail({"world", "clips", pace}, "expected the name of the clip played");
    s.clipNames.push_back(clips[pace].get<std::string>());
  }
  out.fade = c.number(w.value("fade", json(0.3)), {"world", "fade"}, 0, 10);
  out.agents.seed = uint64_t(c.number(w.value("seed", json(1)), {"world", "seed"}, 0, 1e15));
  out.agents.walkSpeed =
      float(c.number(w.value("walk_speed", json(1.3)), {"world", "walk_speed"}, 0.01, 19.9));
  out.agents.runSpeed =
      float(c.number(w.value("run_speed", json(3.2)), {"world", "run_speed"}, 0.01, 19.9));
  out.agents.runners = float(c.number(w.value("runners", json(0.1)), {"world", "runners"}, 0, 1));
}

// "packs": each pack's path (and its impostor's) against the scene file's folder, and its name.
void parsePacks(const Checker &c, const json &j, const std::filesystem::path &dir, Scene &s) {
  if (!j.contains("packs") || !j["packs"].is_array() || j["packs"].empty())
    c.fail({"packs"}, "expected a non-empty list of {\"name\", \"path\"}");
  for (const auto &p : j["packs"]) {
    c.onlyKeys(p, {"packs"}, {"name", "path", "impostor"});
    if (!p.contains("path") || !p["path"].is_string())
      c.fail({"packs"}, "each pack needs a \"path\"");
    s.packPaths.push_back((dir / p["path"].get<std::string>()).lexically_normal().string());
    s.packNames.push_back(
        p.contains("name") ? c.string(p["name"], {"packs", "name"})
                           : std::filesystem::path(p["path"].get<std::string>()).stem().string());
    if (p.contains("impostor") && !p["impostor"].is_string())
      c.fail({"packs", "impostor"}, "expected the path of an impostor pack");
    s.impostorPaths.push_back(
        p.contains("impostor")
            ? (dir / p["impostor"].get<std::string>()).lexically_normal().string()
            : std::string());
  }
}

// How many instances: the scene's count, the override, or with a world its agents (the
// override shared out over the spawn areas, the rest in the last).
size_t instanceCount(const Checker &c, const json &in, size_t instanceOverride, Scene &s) {
  size_t count = size_t(
      c.number(in.value("count", json(1)), {"instances", "count"}, 1, double(limits::kInstances)));
  if (!s.world.enabled())
    return instanceOverride ? instanceOverride : count;
  if (in.contains("count") || in.contains("placement") || in.contains("clip") ||
      in.contains("switch"))
    c.fail({"instances"}, "with a world, the agents give the count (world.spawn), the place and "
                          "the clip (world.clips); leave out count, placement, clip and switch");
  count = 0;
  const uint64_t total = worldAgents(s.world);
  for (size_t k = 0; k < s.world.spawn.size(); ++k) {
    auto &area = s.world.spawn[k];
    if (instanceOverride)
      area.count =
          k + 1 < s.world.spawn.size()
              ? uint32_t(std::llround(double(instanceOverride) * area.count / double(total)))
              : uint32_t(instanceOverride - std::min(count, instanceOverride));
    count += area.count;
  }
  if (count > limits::kInstances)
    c.fail({"world", "spawn"},
           std::to_string(count) + " agents; at most " + std::to_string(limits::kInstances));
  return count;
}

// What instances choose from: the clips and outfits with their weights, how outfits are dealt
// (random: drawn by weight; cycle: instance i wears the (i mod n)-th), and the clip switching.
struct Choices {
  std::vector<double> clipWeights = {1}, outfitWeights = {1};
  bool cycleOutfits = false;
};

Choices parseChoices(const Checker &c, const json &in, uint64_t seed, Scene &s) {
  Choices out;
  std::vector<std::string> clips = {""};
  if (in.contains("clip"))
    c.choices(in["clip"], {"instances", "clip"}, "clip", clips, out.clipWeights);
  if (in.contains("outfit"))
    c.choices(in["outfit"], {"instances", "outfit"}, "outfit", s.outfitNames, out.outfitWeights);
  const json order = in.value("outfit_order", json("random"));
  if (order != "random" && order != "cycle")
    c.fail({"instances", "outfit_order"}, "expected \"random\" or \"cycle\"");
  out.cycleOutfits = order == "cycle";
  if (s.world.enabled())
    clips = s.clipNames;
  s.clipNames = clips;
  if (!in.contains("switch"))
    return out;
  const json &sw = in["switch"];
  const std::vector<std::string> at = {"instances", "switch"};
  c.onlyKeys(sw, at, {"every", "fade"});
  if (!sw.contains("every"))
    c.fail(at, "expected {\"every\": seconds or {\"min\", \"max\"}, \"fade\": seconds}");
  const json &every = sw["every"];
  if (every.is_object()) {
    c.onlyKeys(every, {"instances", "switch", "every"}, {"min", "max"});
    s.switching.minEvery =
        c.number(every.value("min", json(1.0)), {"instances", "switch", "every", "min"}, 0.01, 1e6);
    s.switching.maxEvery =
        c.number(every.value("max", json(s.switching.minEvery)),
                 {"instances", "switch", "every", "max"}, s.switching.minEvery, 1e6);
  } else {
    s.switching.minEvery = s.switching.maxEvery =
        c.number(every, {"instances", "switch", "every"}, 0.01, 1e6);
  }
  s.switching.fade = c.number(sw.value("fade", json(0.3)), {"instances", "switch", "fade"}, 0,
                              s.switching.minEvery);
  s.switching.weights = out.clipWeights;
  s.switching.seed = seed;
  return out;
}

// Where the instances stand: x, z and yaw each (grid, random in a box, or a list repeated to the
// count, which a list without an override sets).
std::vector<glm::dvec3> placeInstances(const Checker &c, const json &in, size_t instanceOverride,
                                       size_t &count, std::mt19937_64 &rng) {
  json placement = in.value("placement", json{{"type", "grid"}});
  if (!placement.is_object())
    c.fail({"instances", "placement"}, "expected an object");
  const std::string type = placement.contains("type")
                               ? c.string(placement["type"], {"instances", "placement", "type"})
                               : "grid";
  std::vector<glm::dvec3> positions;
  if (type == "grid") {
    c.onlyKeys(placement, {"instances", "placement"}, {"type", "spacing"});
    double spacing = c.number(placement.value("spacing", json(1.5)),
                              {"instances", "placement", "spacing"}, 0.01, 1e4);
    size_t side = size_t(std::ceil(std::sqrt(double(count))));
    for (size_t i = 0; i < count; ++i)
      positions.push_back({(double(i % side) - 0.5 * double(side - 1)) * spacing,
                           (double(i / side) - 0.5 * double(side - 1)) * spacing, 0});
  } else if (type == "random") {
    c.onlyKeys(placement, {"instances", "placement"}, {"type", "min", "max"});
    glm::dvec3 lo = c.vec3(placement.value("min", json::array({-10, 0, -10})),
                           {"instances", "placement", "min"});
    glm::dvec3 hi =
        c.vec3(placement.value("max", json::array({10, 0, 10})), {"instances", "placement", "max"});
    std::uniform_real_distribution<double> u(0, 1);
    for (size_t i = 0; i < count; ++i) {
      double x = lo.x + (hi.x - lo.x) * u(rng), z = lo.z + (hi.z - lo.z) * u(rng);
      positions.push_back({x, z, 6.283185307179586 * u(rng)});
    }
  } else if (type == "list") {
    c.onlyKeys(placement, {"instances", "placement"}, {"type", "positions"});
    const json &list = placement.value("positions", json::array());
    if (!list.is_array() || list.empty())
      c.fail({"instances", "placement", "positions"}, "expected [[x, z, yaw_degrees], ...]");
    for (const auto &p : list) {
      if (!p.is_array() || p.size() < 2 || p.size() > 3)
        c.fail({"instances", "placement", "positions"}, "expected [x, z] or [x, z, yaw_degrees]");
      positions.push_back(
          {c.number(p[0], {"instances", "placement", "positions"}, -1e6, 1e6),
           c.number(p[1], {"instances", "placement", "positions"}, -1e6, 1e6),
           p.size() == 3
               ? glm::radians(c.number(p[2], {"instances", "placement", "positions"}, -1e4, 1e4))
               : 0.0});
    }
    if (instanceOverride == 0)
      count = positions.size();
    while (positions.size() < count)
      positions.push_back(positions[positions.size() % list.size()]);
    positions.resize(count);
  } else {
    c.fail({"instances", "placement", "type"},
           "unknown placement '" + type + "' (grid, random, list)");
  }
  return positions;
}

// "palettes": region name -> colour maps; without them one palette, "default" light grey.
void parsePalettes(const Checker &c, const json &j, Scene &s) {
  if (!j.contains("palettes")) {
    s.palettes.push_back({{"default", glm::vec3(0.8f)}});
    return;
  }
  if (!j["palettes"].is_array() || j["palettes"].empty())
    c.fail({"palettes"}, "expected a list of {region: [r, g, b]}");
  for (const auto &p : j["palettes"]) {
    if (!p.is_object())
      c.fail({"palettes"}, "each palette is {region: [r, g, b]}");
    std::vector<std::pair<std::string, glm::vec3>> pal;
    for (auto it = p.begin(); it != p.end(); ++it) {
      glm::dvec3 col = c.vec3(it.value(), {"palettes", it.key()});
      if (glm::any(glm::lessThan(col, glm::dvec3(0))) ||
          glm::any(glm::greaterThan(col, glm::dvec3(1))))
        c.fail({"palettes", it.key()}, "colour components must be in [0, 1]");
      pal.push_back({it.key(), glm::vec3(col)});
    }
    s.palettes.push_back(pal);
  }
}

void parseCamera(const Checker &c, const json &cam, Camera &camera) {
  c.onlyKeys(cam, {"camera"}, {"position", "target", "fov", "near", "far", "path", "loop"});
  if (cam.contains("position"))
    camera.position = c.vec3(cam["position"], {"camera", "position"});
  if (cam.contains("target"))
    camera.target = c.vec3(cam["target"], {"camera", "target"});
  camera.fovYDegrees = c.number(cam.value("fov", json(50)), {"camera", "fov"}, 1, 170);
  camera.nearPlane = c.number(cam.value("near", json(0.1)), {"camera", "near"}, 1e-4, 1e4);
  camera.farPlane =
      c.number(cam.value("far", json(1000)), {"camera", "far"}, camera.nearPlane * 1.001, 1e7);
  camera.loopPath = cam.value("loop", true);
  if (!cam.contains("path"))
    return;
  if (!cam["path"].is_array())
    c.fail({"camera", "path"}, "expected a list of {time, position, target}");
  double last = -1;
  for (const auto &k : cam["path"]) {
    c.onlyKeys(k, {"camera", "path"}, {"time", "position", "target"});
    CameraKey key;
    key.time = c.number(k.value("time", json(0)), {"camera", "path", "time"}, 0, 1e6);
    if (key.time <= last)
      c.fail({"camera", "path", "time"}, "key times must increase");
    last = key.time;
    key.position =
        c.vec3(k.value("position", json::array({0, 1.6, 10})), {"camera", "path", "position"});
    key.target = c.vec3(k.value("target", json::array({0, 1, 0})), {"camera", "path", "target"});
    camera.path.push_back(key);
  }
}

Scene parseSceneText(const std::string &text, const std::string &path, size_t instanceOverride) {
  Checker c(text, path);
  json j = c.parse();
  Scene s;
  s.path = path;
  c.onlyKeys(j, {},
             {"packs", "instances", "palettes", "camera", "light", "budget", "palette_slot",
              "world", "comment"});
  auto dir = std::filesystem::path(path).parent_path();
  if (j.contains("world"))
    parseWorld(c, j["world"], dir, s);
  parsePacks(c, j, dir, s);

  if (!j.contains("instances"))
    c.fail({"instances"}, "missing");
  const json &in = j["instances"];
  c.onlyKeys(in, {"instances"},
             {"count", "pack", "placement", "clip", "outfit", "outfit_order", "time_offset",
              "speed", "seed", "switch"});
  const auto seed = uint64_t(c.number(in.value("seed", json(1)), {"instances", "seed"}, 0, 1e15));
  std::mt19937_64 rng(seed);
  size_t count = instanceCount(c, in, instanceOverride, s);
  uint32_t pack = 0;
  if (in.contains("pack")) {
    auto it = std::find(s.packNames.begin(), s.packNames.end(),
                        c.string(in["pack"], {"instances", "pack"}));
    if (it == s.packNames.end())
      c.fail({"instances", "pack"}, "no pack named " + in["pack"].dump());
    pack = uint32_t(it - s.packNames.begin());
  }
  const Choices choices = parseChoices(c, in, seed, s);
  const std::vector<glm::dvec3> positions = placeInstances(c, in, instanceOverride, count, rng);
  parsePalettes(c, j, s);

  // Every random draw in this order, from the scene's seed: the same scene, the same crowd.
  std::uniform_int_distribution<size_t> pickPalette(0, s.palettes.size() - 1);
  for (size_t i = 0; i < count; ++i) {
    Instance inst;
    inst.pack = pack;
    inst.position = {positions[i].x, 0, positions[i].y};
    inst.yaw = positions[i].z;
    inst.clip = uint32_t(pick(choices.clipWeights, rng));
    inst.timeOffset = c.sample(in.value("time_offset", json{{"min", 0}, {"max", 10}}),
                               {"instances", "time_offset"}, rng, -1e6, 1e6);
    inst.speed = c.sample(in.value("speed", json(1.0)), {"instances", "speed"}, rng, 0, 100);
    inst.palette = uint32_t(pickPalette(rng));
    if (choices.cycleOutfits)
      inst.outfit = uint32_t(i % s.outfitNames.size());
    else if (in.contains("outfit")) // drawn only then: scenes without outfits keep their instances
      inst.outfit = uint32_t(pick(choices.outfitWeights, rng));
    s.instances.push_back(inst);
  }

  if (j.contains("camera"))
    parseCamera(c, j["camera"], s.camera);
  if (j.contains("light")) {
    c.onlyKeys(j["light"], {"light"}, {"direction"});
    glm::dvec3 d =
        c.vec3(j["light"].value("direction", json::array({0.4, 1, 0.6})), {"light", "direction"});
    if (glm::length(d) == 0)
      c.fail({"light", "direction"}, "must not be zero");
    s.lightDirection = glm::vec3(glm::normalize(d));
  }
  if (j.contains("budget"))
    s.budget = uint64_t(c.number(j["budget"], {"budget"}, 0, 1e12));
  if (j.contains("palette_slot")) {
    const json &slot = j["palette_slot"];
    if (slot.is_string() && slot != "clip")
      c.fail({"palette_slot"}, "is \"clip\" or seconds, not " + slot.dump());
    if (!slot.is_string())
      s.paletteSlot = float(c.number(slot, {"palette_slot"}, 0, kMaxPaletteSlot));
  }
  return s;
}

} // namespace

Scene parseScene(const std::string &text, const std::string &path, size_t instanceOverride) {
  try {
    return parseSceneText(text, path, instanceOverride);
  } catch (const json::exception &e) {
    // A value of a type the checks above do not look for where the reader reads it: an error,
    // never a crash (each one the fuzzer finds also gets its own check, with line and column).
    throw Error(path + ": a value of an unexpected type: " + e.what());
  }
}

Scene loadScene(const std::string &path, size_t instanceOverride) {
  const std::vector<uint8_t> bytes =
      readRegularFile(path, {limits::kInputFileBytes, ""}, "scene " + path);
  return parseScene(std::string(bytes.begin(), bytes.end()), path, instanceOverride);
}

} // namespace crowd::runtime
