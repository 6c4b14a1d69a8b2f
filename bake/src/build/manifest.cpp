#include "crowd/bake/manifest.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "crowd/formats/error.h"
#include "crowd/formats/limits.h"
#include "crowd/support/json_checker.h"

namespace crowd {

namespace {

using nlohmann::json;
using support::JsonChecker;
using Keys = JsonChecker::Keys;
namespace fs = std::filesystem;

// An input file named by a manifest: resolved against the manifest's folder and kept inside it
// (or the asset root); must be a regular file within the size bound.
std::string inputFile(const JsonChecker &c, const json &j, const Keys &keys,
                      const InputPolicy &policy) {
  const std::string name = c.string(j, keys);
  std::string p;
  try {
    p = resolveNamedInput(name, c.path(), policy, "file");
    checkInputFile(p, policy);
  } catch (const Error &e) {
    std::string why = e.what();
    if (why.rfind(c.path() + ": ", 0) == 0)
      why = why.substr(c.path().size() + 2);
    c.fail(keys, why);
  }
  return p;
}

std::vector<std::string> names(const JsonChecker &c, const json &j, const Keys &keys) {
  if (!j.is_array())
    c.fail(keys, "expected a list of names");
  std::vector<std::string> out;
  for (const auto &x : j) {
    out.push_back(c.string(x, keys));
    for (size_t k = 0; k + 1 < out.size(); ++k)
      if (out[k] == out.back())
        c.fail(keys, "'" + out.back() + "' is listed twice");
  }
  return out;
}

uint32_t whole(const JsonChecker &c, const json &j, const Keys &keys, double lo, double hi) {
  double v = c.number(j, keys, lo, hi);
  if (v != std::floor(v))
    c.fail(keys, "expected a whole number");
  return uint32_t(v);
}

// "fps": "auto", "source" or a number given as text.
double fpsOf(const JsonChecker &c, const std::string &text, const Keys &keys) {
  try {
    return AnimBakeOptions::parseFps(text);
  } catch (const Error &e) {
    c.fail(keys, e.what());
  }
}

// Runs an option struct's validate() and turns its "field: what" into a located error.
template <class Options> void validate(const JsonChecker &c, const Options &o, const Keys &keys) {
  try {
    o.validate();
  } catch (const Error &e) {
    c.fail(keys, e.what());
  }
}

Keys below(Keys keys, const std::string &key) {
  keys.push_back(key);
  return keys;
}

// "anim": the animation bake's options.
void parseAnim(const JsonChecker &c, const json &a, const Keys &k, AnimBakeOptions &anim) {
  c.onlyKeys(a, k, {"fps", "max_width", "precision", "error_budget_mm", "store"});
  if (a.contains("fps"))
    anim.fps = a["fps"].is_string() ? fpsOf(c, c.string(a["fps"], below(k, "fps")), below(k, "fps"))
                                    : c.number(a["fps"], below(k, "fps"), 1e-3, 1000);
  if (a.contains("error_budget_mm")) {
    const Keys at = below(k, "error_budget_mm");
    anim.errorBudgetMm = c.number(a["error_budget_mm"], at, -HUGE_VAL, HUGE_VAL);
    if (const std::string problem = errorBudgetProblem(anim.errorBudgetMm); !problem.empty())
      c.fail(at, problem);
  }
  if (a.contains("max_width"))
    anim.maxWidth = whole(c, a["max_width"], below(k, "max_width"), 2, limits::kTextureSide);
  if (a.contains("precision"))
    anim.precision = c.string(a["precision"], below(k, "precision"));
  if (a.contains("store"))
    anim.store = c.string(a["store"], below(k, "store"));
  validate(c, anim, k);
}

// "lod": true, false or the LOD bake's options.
void parseLod(const JsonChecker &c, const json &l, const Keys &k, CharacterManifest &m) {
  if (l.is_boolean()) {
    m.lod = l.get<bool>();
  } else {
    c.onlyKeys(l, k, {"floor", "poses", "seam_budget"});
    if (l.contains("floor"))
      m.lodOptions.floorFraction = c.number(l["floor"], below(k, "floor"), 0, 1);
    if (l.contains("seam_budget"))
      m.lodOptions.seamBudget = c.number(l["seam_budget"], below(k, "seam_budget"), 0, 442);
    if (l.contains("poses"))
      m.lodOptions.poses = whole(c, l["poses"], below(k, "poses"), 0, 1024);
    validate(c, m.lodOptions, k);
  }
}

// "visibility": the outfit bake's visibility options.
void parseVisibility(const JsonChecker &c, const json &v, const Keys &k, CharacterManifest &m) {
  auto &vis = m.outfitOptions.visibility;
  c.onlyKeys(v, k,
             {"frame_step", "loop_frames", "rays", "points", "ring", "ground", "regions",
              "min_saving", "check"});
  if (v.contains("loop_frames"))
    vis.loopFrames = whole(c, v["loop_frames"], below(k, "loop_frames"), 0, 100000);
  if (v.contains("frame_step"))
    vis.frameStep = whole(c, v["frame_step"], below(k, "frame_step"), 1, 100000);
  if (v.contains("rays"))
    vis.rays = whole(c, v["rays"], below(k, "rays"), 1, 4096);
  if (v.contains("points"))
    vis.points = whole(c, v["points"], below(k, "points"), 1, 4);
  if (v.contains("ring"))
    vis.ring = whole(c, v["ring"], below(k, "ring"), 0, 64);
  if (v.contains("ground"))
    vis.ground = c.boolean(v["ground"], below(k, "ground"));
  if (v.contains("regions"))
    m.outfitOptions.regions = c.string(v["regions"], below(k, "regions"));
  if (v.contains("min_saving"))
    m.outfitOptions.minSaving = c.number(v["min_saving"], below(k, "min_saving"), 0, 1);
  if (v.contains("check"))
    m.outfitOptions.check = whole(c, v["check"], below(k, "check"), 0, 100000);
}

// "impostor": its options, and the (clip, outfit) pairs baked, each among the character's.
void parseImpostor(const JsonChecker &c, const json &im, const Keys &k, CharacterManifest &m) {
  c.onlyKeys(im, k, {"clips", "outfits", "frames", "views", "texels", "mirror", "measure"});
  std::vector<std::string> clips, outfits;
  if (im.contains("clips"))
    clips = names(c, im["clips"], below(k, "clips"));
  else
    clips = {m.clips.empty() ? std::string() : m.clips.front()}; // "": the first
  if (im.contains("outfits"))
    outfits = names(c, im["outfits"], below(k, "outfits"));
  else if (m.outfits.empty())
    outfits = {""};
  else
    for (const auto &o : m.outfits)
      outfits.push_back(o.first);
  for (const auto &o : outfits) {
    bool known = o.empty(); // the bare body
    for (const auto &[name, file] : m.outfits)
      known = known || name == o;
    if (!known)
      c.fail(below(k, "outfits"), "'" + o + "' is not one of the character's outfits");
  }
  for (const auto &clip : clips)
    if (!m.clips.empty() && std::find(m.clips.begin(), m.clips.end(), clip) == m.clips.end())
      c.fail(below(k, "clips"), "clip '" + clip + "' is not among the character's \"clips\"");
  for (const auto &clip : clips)
    for (const auto &outfit : outfits)
      m.impostorPairs.emplace_back(clip, outfit);
  if (im.contains("frames"))
    m.impostor.frames = whole(c, im["frames"], below(k, "frames"), 1, 4096);
  if (im.contains("texels"))
    m.impostor.texels = whole(c, im["texels"], below(k, "texels"), 4, 4096);
  if (im.contains("mirror"))
    m.impostor.mirror = c.boolean(im["mirror"], below(k, "mirror"));
  if (im.contains("measure"))
    m.impostor.measure = c.boolean(im["measure"], below(k, "measure"));
  if (im.contains("views")) {
    std::string views = c.string(im["views"], below(k, "views"));
    unsigned a = 0, e = 0;
    char x = 0;
    std::istringstream in(views);
    if (!(in >> a >> x >> e) || x != 'x' || !in.eof())
      c.fail(below(k, "views"), "expected \"AxE\", e.g. \"32x8\", got '" + views + "'");
    m.impostor.azimuths = a;
    m.impostor.elevations = e;
  }
  validate(c, m.impostor, k);
}

// "cloth": the cloth loops, each of a known outfit and clip, no two of one garment and clip.
void parseCloth(const JsonChecker &c, const json &list, const Keys &keys, const InputPolicy &policy,
                CharacterManifest &m) {
  if (!list.is_array())
    c.fail(keys, "expected [{\"outfit\", \"garment\", \"clip\", \"cache\"}, ...]");
  for (size_t i = 0; i < list.size(); ++i) {
    const Keys k = below(keys, std::to_string(i));
    const json &e = list[i];
    c.onlyKeys(e, k,
               {"outfit", "garment", "clip", "cache", "fps", "blend", "candidates", "views",
                "max_cycles"});
    for (const char *required : {"outfit", "garment", "clip", "cache"})
      if (!e.contains(required))
        c.fail(k, std::string("a cloth loop needs \"") + required + "\"");
    ClothEntry cl;
    cl.outfit = c.string(e["outfit"], below(k, "outfit"));
    cl.garment = c.string(e["garment"], below(k, "garment"));
    cl.clip = c.string(e["clip"], below(k, "clip"));
    cl.cache = inputFile(c, e["cache"], below(k, "cache"), policy);
    if (std::none_of(m.outfits.begin(), m.outfits.end(),
                     [&](const auto &o) { return o.first == cl.outfit; }))
      c.fail(below(k, "outfit"), "'" + cl.outfit + "' is not one of the character's outfits");
    if (!m.clips.empty() && std::find(m.clips.begin(), m.clips.end(), cl.clip) == m.clips.end())
      c.fail(below(k, "clip"), "clip '" + cl.clip + "' is not among the character's \"clips\"");
    for (const auto &other : m.cloth)
      if (other.outfit == cl.outfit && other.garment == cl.garment && other.clip == cl.clip)
        c.fail(k, "a second loop of garment '" + cl.garment + "' of outfit '" + cl.outfit +
                      "' over clip '" + cl.clip + "'");
    auto &o = cl.options;
    if (e.contains("fps"))
      o.cache.fps = c.number(e["fps"], below(k, "fps"), 0, 1000);
    if (e.contains("blend")) { // a whole number of frames, or -1: what the seam needs
      const double blend = c.number(e["blend"], below(k, "blend"), -1, 100000);
      if (blend != std::floor(blend))
        c.fail(below(k, "blend"), "expected a whole number of frames (-1: what the seam needs)");
      o.blend = int(blend);
    }
    if (e.contains("candidates"))
      o.loop.search.candidates = whole(c, e["candidates"], below(k, "candidates"), 1, 100);
    if (e.contains("views"))
      o.loop.edges.views = whole(c, e["views"], below(k, "views"), 1, 64);
    if (e.contains("max_cycles"))
      o.loop.search.maxCycles = whole(c, e["max_cycles"], below(k, "max_cycles"), 0, 100000);
    validate(c, o, k);
    m.cloth.push_back(std::move(cl));
  }
}

// "limits": {"seconds": 600, "memory_mib": 4096}: bounds on each of the character's jobs.
void parseLimits(const JsonChecker &c, const json &l, const Keys &k, JobLimits &limits) {
  if (!l.is_object())
    c.fail(k, "expected {\"seconds\": S, \"memory_mib\": M}");
  c.onlyKeys(l, k, {"seconds", "memory_mib"});
  if (l.contains("seconds"))
    limits.maxSeconds = c.number(l["seconds"], below(k, "seconds"), 0.001, JobLimits::kMostSeconds);
  if (l.contains("memory_mib"))
    limits.maxMemoryMiB = uint64_t(
        c.number(l["memory_mib"], below(k, "memory_mib"), 1, double(JobLimits::kMostMemoryMiB)));
}

CharacterManifest parse(const JsonChecker &c, const json &j, const Keys &at,
                        const InputPolicy &policy) {
  auto key = [&](const std::string &k) { return below(at, k); };
  c.onlyKeys(j, at,
             {"name", "body", "outfits", "clips", "mesh", "anim", "lod", "visibility", "impostor",
              "cloth", "limits", "comment"});
  CharacterManifest m;
  m.source = c.path();
  if (!j.contains("name"))
    c.fail(at, "a character needs a \"name\"");
  if (!j.contains("body"))
    c.fail(at, "a character needs a \"body\" (its glTF file)");
  m.name = c.string(j["name"], key("name"));
  for (char ch : m.name)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_' && ch != '-' && ch != '.')
      c.fail(key("name"), "'" + m.name +
                              "' may hold only letters, digits, '_', '-' and '.' "
                              "(it names the pack file)");
  m.input = policy;
  m.body = inputFile(c, j["body"], key("body"), policy);
  if (j.contains("outfits")) {
    const json &o = j["outfits"];
    if (!o.is_object())
      c.fail(key("outfits"), "expected {\"name\": \"file.glb\", ...}");
    for (auto it = o.begin(); it != o.end(); ++it) {
      Keys k = key("outfits");
      k.push_back(it.key());
      m.outfits.emplace_back(it.key(), inputFile(c, it.value(), k, policy));
    }
  }
  if (j.contains("clips"))
    m.clips = names(c, j["clips"], key("clips"));
  if (j.contains("mesh"))
    m.mesh = c.string(j["mesh"], key("mesh"));
  if (j.contains("anim"))
    parseAnim(c, j["anim"], key("anim"), m.anim);
  if (j.contains("lod"))
    parseLod(c, j["lod"], key("lod"), m);
  if (j.contains("visibility"))
    parseVisibility(c, j["visibility"], key("visibility"), m);
  m.outfitOptions.setAnimation(m.anim); // the outfit bake's animation is the character's
  validate(c, m.outfitOptions, key("visibility"));
  if (j.contains("impostor"))
    parseImpostor(c, j["impostor"], key("impostor"), m);
  if (j.contains("cloth"))
    parseCloth(c, j["cloth"], key("cloth"), policy, m);
  if (j.contains("limits"))
    parseLimits(c, j["limits"], key("limits"), m.limits);
  return m;
}

} // namespace

nlohmann::ordered_json ClothEntry::canonical() const {
  nlohmann::ordered_json j = {{"outfit", outfit},
                              {"garment", garment},
                              {"clip", clip},
                              {"fps", options.cache.fps},
                              {"blend", options.blend},
                              {"candidates", options.loop.search.candidates},
                              {"views", options.loop.edges.views}};
  if (options.loop.search.maxCycles != 0) // absent when unset: earlier keys stay valid
    j["max_cycles"] = options.loop.search.maxCycles;
  return j;
}

nlohmann::ordered_json CharacterManifest::canonical() const {
  nlohmann::ordered_json j;
  j["name"] = name;
  j["clips"] = clips;
  j["mesh"] = mesh;
  j["anim"] = {{"fps", anim.fps > 0 ? nlohmann::ordered_json(anim.fps)
                                    : nlohmann::ordered_json(AnimBakeOptions::fpsName(anim.fps))},
               {"max_width", anim.maxWidth},
               {"precision", anim.precision},
               {"error_budget_mm", anim.errorBudgetMm}};
  if (anim.store != "texture") // absent for what every earlier key meant: those stay valid
    j["anim"]["store"] = anim.store;
  if (lod)
    j["lod"] = {{"floor", lodOptions.floorFraction},
                {"poses", lodOptions.poses},
                {"seam_budget", lodOptions.seamBudget}};
  else
    j["lod"] = false;
  for (const auto &[outfit, file] : outfits)
    j["outfits"].push_back(outfit);
  if (!outfits.empty()) {
    const auto &v = outfitOptions.visibility;
    j["visibility"] = {{"frame_step", v.frameStep},
                       {"rays", v.rays},
                       {"points", v.points},
                       {"ring", v.ring},
                       {"ground", v.ground},
                       {"regions", outfitOptions.regions},
                       {"min_saving", outfitOptions.minSaving}};
    if (outfitOptions.check > 0) // only when asked: other keys stay as they were
      j["visibility"]["check"] = outfitOptions.check;
    if (!cloth.empty()) // only with loops, likewise
      j["visibility"]["loop_frames"] = v.loopFrames;
  }
  if (!impostorPairs.empty()) {
    auto &im = j["impostor"];
    for (const auto &[clip, outfit] : impostorPairs)
      im["pairs"].push_back({clip, outfit});
    im["frames"] = impostor.frames;
    im["views"] = std::to_string(impostor.azimuths) + "x" + std::to_string(impostor.elevations);
    if (impostor.switchDistance > 0)
      im["texels"] = {{"switch_distance", impostor.switchDistance},
                      {"screen_height", impostor.screenHeight},
                      {"fov", impostor.fovDegrees}};
    else
      im["texels"] = impostor.texels;
    im["mirror"] = impostor.mirror;
    if (impostor.measure)
      im["measure"] = true;
  }
  for (const auto &c : cloth)
    j["cloth"].push_back(c.canonical());
  if (terrain) {
    const TerrainOptions &t = *terrain;
    j["terrain"] = {{"cell", t.cell},
                    {"light", {t.light.x, t.light.y, t.light.z}},
                    {"step", t.stepHeight},
                    {"max_slope", t.maxSlopeDeg}};
  }
  return j;
}

CharacterManifest parseManifest(const std::string &text, const std::string &path,
                                const InputPolicy &policy) {
  JsonChecker c(text, path);
  return parse(c, c.parse(), {}, policy);
}

namespace {

// Every entry of the library, or only `only`'s.
Library load(const std::string &path, const InputPolicy &policy, std::optional<size_t> only) {
  const std::string text = readInputText(path, policy);
  JsonChecker c(text, path);
  const json j = c.parse();
  Library lib;
  lib.path = path;
  if (!j.is_object())
    c.fail({}, "expected a character manifest or {\"characters\": [...]}");
  if (!j.contains("characters")) {
    lib.single = true;
    lib.characters.push_back(parse(c, j, {}, policy));
    return lib;
  }
  c.onlyKeys(j, {}, {"characters", "comment"});
  const json &list = j["characters"];
  if (!list.is_array() || list.empty())
    c.fail({"characters"}, "expected a non-empty list of manifest files or objects");
  if (only && *only >= list.size())
    c.fail({"characters"}, "has no entry " + std::to_string(*only));
  for (size_t i = only.value_or(0); i < (only ? *only + 1 : list.size()); ++i) {
    const json &entry = list[i];
    const Keys at = {"characters", std::to_string(i)};
    if (entry.is_string()) {
      const std::string file = inputFile(c, entry, at, policy);
      const std::string sub = readInputText(file, policy);
      JsonChecker sc(sub, file);
      const json sj = sc.parse();
      if (sj.is_object() && sj.contains("characters"))
        c.fail(at, "'" + file + "' is a library, not a character manifest");
      lib.characters.push_back(parse(sc, sj, {}, policy));
    } else if (entry.is_object()) {
      lib.characters.push_back(parse(c, entry, at, policy));
    } else {
      c.fail(at, "expected a manifest file name or an inline manifest object");
    }
    lib.characters.back().entry = i;
  }
  std::set<std::string> seen;
  for (const auto &m : lib.characters)
    if (!seen.insert(m.name).second)
      c.fail({"characters"}, "two characters are named '" + m.name + "'");
  return lib;
}

} // namespace

Library loadLibrary(const std::string &path, const InputPolicy &policy) {
  return load(path, policy, std::nullopt);
}

Library loadLibrary(const std::string &path, const InputPolicy &policy, size_t entry) {
  return load(path, policy, entry);
}

} // namespace crowd
