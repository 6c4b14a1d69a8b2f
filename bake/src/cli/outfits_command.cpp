// crowdbake outfits: a body template and pre-fitted outfits into one clothed-crowd pack.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>

#include "args.h"
#include "commands.h"
#include "crowd/bake/import.h"
#include "crowd/bake/outfit_bake.h"
#include "crowd/bake/provenance.h"
#include "crowd/formats/error.h"
#include "crowd/formats/limits.h"

using nlohmann::ordered_json;

namespace crowd::cli {

namespace {

const char *const kDescription = R"(The "tagged" method of clothed crowds: the body template keeps
its sub-meshes (one per material); each outfit's garments, skinned to the same skeleton (joints
matched by name), are added. For each outfit and body sub-mesh the bake decides, over every
frame of every clip, whether the sub-mesh is visible, hidden (never drawn with that outfit) or
partial (drawn through an outfit-specific copy holding only its visible faces). A body face is
hidden only if, in every tested frame, rays from points on it over its whole outward hemisphere
all hit the garments or the body. Alpha-masked or blended garments never hide anything.
crowdplay draws the pack with an outfit per character (scene file: "outfit").)";

std::pair<std::string, std::string> nameAndFile(const std::string &arg) {
  if (auto eq = arg.find('='); eq != std::string::npos && eq > 0)
    return {arg.substr(0, eq), arg.substr(eq + 1)};
  std::string stem = std::filesystem::path(arg).stem().string();
  if (stem.rfind("outfit_", 0) == 0 && stem.size() > 7)
    stem = stem.substr(7);
  return {stem, arg};
}

} // namespace

int cmdOutfits(int argc, char **argv) {
  CLI::App app(kDescription, "crowdbake outfits");
  example(app, "crowdbake outfits humanoid.glb --outfit outfit_dress.glb --outfit "
               "outfit_jumper_skirt.glb -o clothed.crowdpack --check 4 --report clothed.json");
  BakeArgs b;
  b.add(app);
  OutfitOptions opt;
  auto &vis = opt.visibility;
  std::vector<std::string> outfitArgs;
  uint32_t check = 0;
  bool noGround = !vis.ground;
  app.add_option("--outfit", outfitArgs,
                 "[NAME=]FILE: an outfit (repeatable); its name defaults to the file name "
                 "without extension and without an \"outfit_\" prefix")
      ->required();
  app.add_option("--frame-step", vis.frameStep, "test every K-th frame of each clip")
      ->capture_default_str();
  app.add_option("--rays", vis.rays,
                 "azimuths on the lowest ring (1 degree up) of the directions each face casts "
                 "over its outward hemisphere; N/3 rings, denser near the horizon (24: 139 "
                 "directions)")
      ->capture_default_str();
  app.add_option("--points", vis.points, "points per face rays leave from: 1 (centroid) or 4")
      ->capture_default_str();
  app.add_flag("--no-ground", noGround,
               "rays that go below the body's lowest point escape too (default: a ground plane "
               "there occludes them, as no camera looks from below it)");
  app.add_option("--regions", opt.regions,
                 "body sub-meshes: material (one per glTF material) or joint (each material "
                 "split by the joint weighing most on each face: finer regions, so fewer faces "
                 "go into outfit-specific copies)")
      ->capture_default_str();
  app.add_option("--ring", vis.ring, "keep faces within N vertex steps of a visible face (0: off)")
      ->capture_default_str();
  app.add_option("--min-saving", opt.minSaving,
                 "write an outfit-specific copy of a partial sub-mesh only when it leaves out at "
                 "least this share of its faces; otherwise draw the sub-mesh whole")
      ->capture_default_str();
  app.add_option("--check", check,
                 "after baking, prove no hole opens: render every outfit naively and culled from "
                 "the 32x8 impostor views and 16 player-like views at every K-th frame of every "
                 "clip and compare pixels (0: no check); a differing pixel fails the bake")
      ->capture_default_str();
  app.add_option("--fps", opt.anim.fps, "animation sampling rate, as in crowdbake anim")
      ->capture_default_str();
  addTextureOptions(app, opt.anim);
  addThreads(app, vis.threads);
  if (!parseArgs(app, argc, argv))
    return 0;
  b.files.finish();
  vis.ground = !noGround;
  vis.fps = opt.anim.fps;
  opt.anim.threads = vis.threads;
  validated(opt);
  if (check > 100000)
    throw UsageError("--check: must be in [0, 100000]");
  ResourceGuard guard(b.files.limits, "crowdbake outfits " + b.input);
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  Reporter reporter;
  reporter.quiet = b.quiet;
  const bool progress = b.progress();
  auto say = [&](const std::string &s) {
    if (progress)
      std::fprintf(stderr, "crowdbake: %s\n", s.c_str());
  };

  ImportOptions io;
  io.input = b.files.policy;
  say("importing " + b.input);
  Character body = importGltf(b.input, io, reporter);
  std::vector<OutfitInput> outfits;
  std::vector<std::string> sources = body.sourceFiles;
  for (const auto &arg : outfitArgs) {
    auto [name, file] = nameAndFile(arg);
    for (const auto &o : outfits)
      if (o.name == name)
        throw UsageError("two outfits are named '" + name + "' (use --outfit NAME=FILE)");
    say("importing outfit '" + name + "' from " + file);
    outfits.push_back({name, importGltf(file, io, reporter)});
    sources.insert(sources.end(), outfits.back().character.sourceFiles.begin(),
                   outfits.back().character.sourceFiles.end());
  }
  const auto t1 = Clock::now();
  say("deciding visibility of " + std::to_string(body.mesh.indices.size() / 3) +
      " body faces for " + std::to_string(outfits.size()) + " outfit(s)");
  OutfitBakeResult r = bakeOutfits(body, outfits, opt, reporter);
  auto &pack = r.anim.pack;
  std::vector<std::pair<std::string, std::string>> settings = {
      {"command", "outfits"},
      {"fps", std::to_string(opt.anim.fps)},
      {"max-width", std::to_string(opt.anim.maxWidth)},
      {"precision", opt.anim.precision},
      {"frame-step", std::to_string(vis.frameStep)},
      {"rays", std::to_string(vis.rays)},
      {"points", std::to_string(vis.points)},
      {"ring", std::to_string(vis.ring)},
      {"min-saving", std::to_string(opt.minSaving)},
      {"regions", opt.regions},
      {"ground", vis.ground ? "yes" : "no"}};
  for (const auto &o : outfits)
    settings.emplace_back("outfit", o.name);
  pack.provenance = makeProvenance(sources, settings);
  const auto t2 = Clock::now();

  HoleCheck holes;
  if (check > 0) {
    say("hole check: rendering every outfit naively and culled at every " + std::to_string(check) +
        "th frame");
    HoleCheckOptions ho;
    ho.frameStep = check;
    ho.threads = vis.threads;
    holes = checkHoles(r, ho);
  }
  const auto t3 = Clock::now();
  // Written only when the check passes, so a failed proof leaves no pack behind.
  for (const auto &o : holes.outfits)
    if (o.differingPixels > 0) {
      std::map<std::string, int> where; // leaked faces per body sub-mesh
      for (uint32_t t : o.leaked)
        for (const auto &part : body.mesh.parts)
          if (t * 3 >= part.firstIndex && t * 3 < part.firstIndex + part.indexCount)
            ++where[part.name];
      std::string list;
      for (const auto &[part, count] : where)
        list += (list.empty() ? "" : ", ") + part + " " + std::to_string(count);
      throw Error("hole check failed: outfit '" + o.name + "' differs from the naive render in " +
                  std::to_string(o.differingPixels) + " pixels of " + std::to_string(o.images) +
                  " images; removed faces seen: " + list +
                  " (try --ring 2, more --rays, or --frame-step 1)");
    }
  const auto bytes = pack::packBytes(pack);
  pack::writeFileAtomic(b.output, bytes);

  const double n = double(outfits.size());
  const double body0 = r.bodyTriangles;
  const double garments = (double(r.naiveFaces) - body0) / n;
  const double prefitted = double(r.prefittedFaces) / n, specific = double(r.specificFaces) / n;
  for (const auto &o : r.outfits) {
    std::string line = "outfit '" + o.name + "': " + std::to_string(o.removedFaces) + " of " +
                       std::to_string(r.bodyTriangles) + " body faces removed;";
    for (const auto &s : o.subMeshes)
      line += " " + s.subMesh + " " + s.coverage + (s.keptWhole ? " (kept whole)" : "");
    say(line);
  }
  say("faces stored: naive " + std::to_string(r.naiveFaces) + ", pre-fitted " +
      std::to_string(r.prefittedFaces) + ", tagged " + std::to_string(r.taggedFaces) + " (" +
      std::to_string(r.specificFaces) + " in outfit-specific sub-meshes)");
  for (const auto &o : holes.outfits)
    say("hole check '" + o.name + "': " + std::to_string(o.differingPixels) +
        " differing pixels in " + std::to_string(o.images) + " images; recall " +
        std::to_string(o.recall()));
  say("wrote " + b.output + " (" + std::to_string(bytes.size()) + " bytes)");

  if (!b.report.empty()) {
    auto secs = [](auto d) { return std::chrono::duration<double>(d).count(); };
    ordered_json j;
    j["command"] = "outfits";
    j["body"] = b.input;
    j["output"] = b.output;
    j["pack_bytes"] = bytes.size();
    j["body_faces"] = r.bodyTriangles;
    j["body_faces_hidden_without_outfit"] = r.bareHiddenFaces;
    j["frames_tested"] = r.framesTested;
    j["min_saving"] = opt.minSaving;
    for (const auto &o : r.outfits) {
      ordered_json oj;
      oj["name"] = o.name;
      oj["garment_faces"] = o.garmentFaces;
      oj["hidden_faces"] = o.hiddenFaces;
      oj["removed_faces"] = o.removedFaces;
      oj["visibility_s"] = o.seconds;
      for (const auto &s : o.subMeshes)
        oj["sub_meshes"].push_back({{"name", s.subMesh},
                                    {"faces", s.faces},
                                    {"hidden", s.hidden},
                                    {"coverage", s.coverage},
                                    {"kept_whole", s.keptWhole}});
      j["outfits"].push_back(oj);
    }
    j["faces_stored"] = {
        {"naive", r.naiveFaces},
        {"prefitted", r.prefittedFaces},
        {"tagged", r.taggedFaces},
        {"outfit_specific", r.specificFaces},
        {"outfit_specific_share", double(r.specificFaces) / double(r.taggedFaces)},
        {"tagged_over_naive", double(r.taggedFaces) / double(r.naiveFaces)},
        {"tagged_over_prefitted", double(r.taggedFaces) / double(r.prefittedFaces)}};
    // Figure 6 of the seed: storage as outfits are added, from these outfits' means.
    for (int k = 1; k <= 10; ++k)
      j["extrapolated"].push_back({{"outfits", k},
                                   {"naive", body0 + k * garments},
                                   {"prefitted", k * prefitted},
                                   {"tagged", body0 + k * (specific + garments)}});
    for (const auto &o : holes.outfits)
      j["hole_check"]["outfits"].push_back({{"name", o.name},
                                            {"images", o.images},
                                            {"differing_pixels", o.differingPixels},
                                            {"removed_faces", o.removed},
                                            {"never_seen_faces", o.neverSeen},
                                            {"removed_never_seen", o.removedUnseen},
                                            {"recall", o.recall()}});
    if (check > 0) {
      j["hole_check"]["frame_step"] = check;
      j["hole_check"]["frames"] = holes.frames;
      j["hole_check"]["views"] = holes.views;
    }
    j["time_s"] = {{"import", secs(t1 - t0)},
                   {"bake", secs(t2 - t1)},
                   {"hole_check", secs(t3 - t2)},
                   {"total", secs(Clock::now() - t0)}};
    j["warnings"] = warningsJson(reporter);
    writeJson(b.report, j);
  }
  return 0;
}

} // namespace crowd::cli
