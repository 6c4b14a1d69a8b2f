// crowdbake: the command-line front of the bake library. Sub-commands like git; every
// failure is one line on stderr and a non-zero exit (1 bad input or failed bake, 2 bad usage).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "args.h"
#include "commands.h"
#include "crowd/bake/anim_bake.h"
#include "crowd/bake/anim_report.h"
#include "crowd/bake/import.h"
#include "crowd/bake/impostor_bake.h"
#include "crowd/bake/lod_bake.h"
#include "crowd/bake/provenance.h"
#include "crowd/bake/resource_guard.h"
#include "crowd/formats/chunks.h"
#include "crowd/formats/error.h"
#include "crowd/formats/impostor.h"
#include "crowd/formats/limits.h"
#include "crowd/samples/samples.h"

using nlohmann::ordered_json;
using namespace crowd::cli;

namespace {

const char *kTopHelp = R"(crowdbake: bake glTF characters into crowdpack files for real-time crowds

usage: crowdbake <command> [options]

commands:
  build     character manifests and libraries into character packs (jobs, content cache),
            locally or on a Slurm cluster
  samples   write the bundled sample characters (humanoid and three outfits) as .glb
  anim      bake animation textures, skin weights and mesh from a glTF character
  lod       anim, plus continuous LOD: the mesh ordered for edge-collapse cuts at any vertex count
  outfits   body template + pre-fitted outfits: per outfit, which body sub-meshes are visible,
            hidden or partial over every frame, and outfit-specific copies of partial ones
  impostor  bake per-frame atlases of views (normals, region ids) for far-away characters
  inspect   list a pack's chunks, joints, clips, textures and sizes
  verify    check every offset, size, checksum and cross-reference of a pack
  export    write a pack's textures as images

Run 'crowdbake <command> --help' for a command's options.

example:
  crowdbake samples --out s && crowdbake anim s/humanoid.glb -o h.crowdpack --report r.json
)";

const char *const kSamplesHelp = R"(Writes humanoid.glb, outfit_dress.glb, outfit_jumper_skirt.glb
and outfit_shirt_trousers.glb into DIR. The output is deterministic: the same bytes on every
run.)";

const char *const kAnimHelp = R"(Samples every clip's joint matrices (global joint transform x
inverse bind) into one animation texture, stores skin weights (2 texels per vertex) and the
mesh, then checks the texture against exact evaluation of the glTF with the player's
interpolation (at frames, mid-frames and random times) and reports the error.)";

const char *const kLodHelp = R"(Bakes what crowdbake anim bakes, with the mesh ordered for
continuous LOD: the full edge-collapse sequence down to a floor, so a renderer can draw any
vertex count v by taking each sub-mesh's first triangles (their count for v is stored) and
following indices through the collapse map until they are below v. Collapses run on a welded
half-edge mesh (OpenMesh) by quadric cost summed over the bind pose and poses sampled from every
clip (skinning-aware); a UV or normal seam vertex collapses only along its seam, a boundary
vertex only along its boundary; no cut has a degenerate triangle or one turned more than 75
degrees from its full-detail normal. No new vertices. Non-manifold, duplicate and zero-area
triangles are repaired and reported.)";

const char *const kImpostorHelp = R"(For sampled frames of a clip, renders the character from
azimuths x elevations over the upper hemisphere with the deterministic rasterizer: object-space
normals (RGB) with the region (sub-mesh) id + 1 in alpha, each view cropped to its silhouette,
dilated (empty texels copy their nearest covered neighbour, region 0) and shelf-packed into one
atlas per frame, with a 16-bit UV map and a best impostor plane per view. crowdplay draws the
pack for instances of this clip past the distance where a texel covers a pixel (scene file:
"impostor" in a pack).)";

int cmdSamples(int argc, char **argv) {
  CLI::App app(kSamplesHelp, "crowdbake samples");
  example(app, "crowdbake samples --out samples_out");
  std::string out;
  app.add_option("--out", out, "folder to write the samples into")->required();
  if (!parseArgs(app, argc, argv))
    return 0;
  crowd::samples::writeSamples(out);
  for (const auto &f : crowd::samples::kFiles)
    std::cout << out << "/" << f << "\n";
  return 0;
}

int cmdAnim(int argc, char **argv, const std::string &command) {
  const bool lodCommand = command == "lod";
  CLI::App app(lodCommand ? kLodHelp : kAnimHelp, "crowdbake " + command);
  example(app, lodCommand
                   ? "crowdbake lod humanoid.glb -o humanoid.crowdpack --report r.json"
                   : "crowdbake anim humanoid.glb -o humanoid.crowdpack --fps 30 --report r.json");
  BakeArgs b;
  b.add(app);
  crowd::AnimBakeOptions opt;
  crowd::ImportOptions io;
  crowd::LodOptions lodOpt;
  std::string fpsText = CLI::detail::to_string(opt.fps);
  bool lodFlag = false;
  app.add_option("--clip", opt.clip, "bake only this clip (default: every clip)");
  app.add_option("--mesh", io.mesh,
                 "bake only this mesh (default: every mesh bound to the largest skin)");
  app.add_option("--fps", fpsText,
                 "sampling rate, frames per second; \"source\" uses each clip's own key rate, "
                 "so baked frames sit on the keys")
      ->capture_default_str();
  addTextureOptions(app, opt);
  addThreads(app, opt.threads);
  CLI::Option *lodOption = nullptr;
  if (!lodCommand)
    lodOption = app.add_flag("--lod", lodFlag, "add continuous LOD (as crowdbake lod does)");
  const char *lodGroup = lodCommand ? "Options" : "LOD (with --lod)";
  auto *floorOpt =
      app.add_option("--floor", lodOpt.floorFraction,
                     "stop collapsing at this share of the triangles, or where no legal "
                     "collapse is left")
          ->capture_default_str()
          ->group(lodGroup);
  auto *posesOpt = app.add_option("--poses", lodOpt.poses,
                                  "animation poses in the collapse cost, spread over all clips; 0: "
                                  "the bind pose alone")
                       ->capture_default_str()
                       ->group(lodGroup);
  if (lodOption) {
    floorOpt->needs(lodOption);
    posesOpt->needs(lodOption);
  }
  if (!parseArgs(app, argc, argv))
    return 0;
  b.files.finish();
  const bool lod = lodCommand || lodFlag;
  if (fpsText == "source") {
    opt.fps = 0;
  } else {
    try {
      size_t used = 0;
      opt.fps = std::stod(fpsText, &used);
      if (used != fpsText.size() || !(opt.fps > 0))
        throw std::invalid_argument(fpsText);
    } catch (const std::exception &) {
      throw UsageError("--fps: expects a number > 0 or source, got '" + fpsText + "'");
    }
  }
  validated(opt);
  validated(lodOpt);
  io.input = b.files.policy;
  crowd::ResourceGuard guard(b.files.limits, "crowdbake " + command + " " + b.input);
  using Clock = std::chrono::steady_clock;
  auto t0 = Clock::now();
  crowd::Reporter reporter;
  reporter.quiet = b.quiet;
  const std::string &input = b.input;
  const bool progress = b.progress();
  if (progress)
    std::fprintf(stderr, "crowdbake: importing %s\n", input.c_str());
  crowd::Character character = crowd::importGltf(input, io, reporter);
  const size_t inputTriangles = character.mesh.indices.size() / 3;
  auto t1 = Clock::now();
  std::optional<crowd::pack::Lod> lodChunk;
  double lodSeconds = 0;
  if (lod) {
    if (progress)
      std::fprintf(stderr, "crowdbake: collapsing %zu triangles\n", inputTriangles);
    lodChunk = crowd::applyLod(character, lodOpt, reporter);
    lodSeconds = std::chrono::duration<double>(Clock::now() - t1).count();
  }

  if (progress)
    std::fprintf(stderr, "crowdbake: sampling and checking %zu clip(s)\n", character.clips.size());
  crowd::AnimBakeResult result = crowd::bakeAnimation(character, opt, reporter);
  result.pack.lod = lodChunk;
  auto t2 = Clock::now();

  std::ostringstream fps;
  if (opt.fps > 0)
    fps << opt.fps;
  else
    fps << "source";
  std::vector<std::pair<std::string, std::string>> settings = {
      {"command", command},
      {"clip", opt.clip},
      {"mesh", io.mesh},
      {"fps", fps.str()},
      {"max-width", std::to_string(opt.maxWidth)},
      {"precision", opt.precision}};
  if (lod)
    settings.insert(settings.end(), {{"lod-floor", std::to_string(lodOpt.floorFraction)},
                                     {"lod-poses", std::to_string(lodOpt.poses)}});
  result.pack.provenance = crowd::makeProvenance(character.sourceFiles, settings);
  std::vector<uint8_t> bytes = crowd::pack::packBytes(result.pack);
  crowd::pack::writeFileAtomic(b.output, bytes);
  auto t3 = Clock::now();

  if (!b.report.empty()) {
    auto secs = [](auto d) { return std::chrono::duration<double>(d).count(); };
    ordered_json r;
    r["command"] = command;
    r["input"] = input;
    r["output"] = b.output;
    r["baker_version"] = crowd::kBakerVersion;
    r["joints"] = character.jointCount();
    r["vertices"] = character.mesh.vertexCount();
    r["triangles"] = character.mesh.indices.size() / 3;
    r["diagonal"] = result.diagonal;
    r["mm_per_model_unit"] = result.mmPerUnit; // the character scaled to 1.8 m
    r["scaled_by"] = result.heightIsDiagonal ? "diagonal" : "height";
    r["pack_bytes"] = bytes.size();
    r["precision"] = opt.precision;
    r["time_s"] = {{"import", secs(t1 - t0)},
                   {"bake_and_check", secs(t2 - t1)},
                   {"write", secs(t3 - t2)},
                   {"total", secs(t3 - t0)}};
    const auto &baked = result.accuracy[result.baked];
    r["bytes_per_joint_per_frame"] = baked.precision.bytesPerJointPerFrame();
    for (size_t i = 0; i < result.pack.clips.size(); ++i) {
      const auto &c = result.pack.clips[i];
      const auto &acc = baked.clips[i];
      ordered_json cj;
      cj["name"] = c.name;
      cj["frames"] = c.frameCount;
      cj["fps"] = c.fps;
      cj["start_time"] = c.startTime;
      cj["loop"] = c.loop;
      cj.update(crowd::clipErrorsJson(acc, result));
      r["clips"].push_back(cj);
    }
    for (const auto &pa : result.accuracy)
      r["precisions"].push_back(crowd::precisionJson(pa, result));
    if (lodChunk) {
      const auto &l = *lodChunk;
      const uint32_t n = uint32_t(l.collapse.size());
      auto triangles = [&](uint32_t v) { return l.totalTriangles(v); };
      ordered_json lj;
      lj["input_triangles"] = inputTriangles;
      lj["triangles"] = triangles(n);
      lj["vertices"] = n;
      lj["floor_vertices"] = l.floorVertices;
      lj["floor_triangles"] = triangles(l.floorVertices);
      lj["time_s"] = lodSeconds;
      lj["input_triangles_per_s"] = double(inputTriangles) / std::max(lodSeconds, 1e-9);
      for (double share : {0.5, 0.25, 0.1, 0.05}) { // the fewest vertices holding the share
        uint32_t v = n;
        while (v > l.floorVertices && double(triangles(v - 1)) >= share * double(triangles(n)))
          --v;
        lj["levels"].push_back({{"share", share},
                                {"vertices", v},
                                {"triangles", triangles(v)},
                                {"quadric_error", l.error[std::min(v, n - 1)]}});
      }
      r["lod"] = lj;
    }
    r["warnings"] = warningsJson(reporter);
    writeJson(b.report, r);
  }
  if (progress)
    std::fprintf(stderr, "crowdbake: wrote %s (%zu bytes)\n", b.output.c_str(), bytes.size());
  return 0;
}

int cmdImpostor(int argc, char **argv) {
  CLI::App app(kImpostorHelp, "crowdbake impostor");
  example(app,
          "crowdbake impostor humanoid.glb -o walk_impostor.crowdpack --clip walk --frames 16");
  BakeArgs b;
  b.add(app);
  crowd::ImpostorOptions opt;
  crowd::ImportOptions io;
  std::string views = std::to_string(opt.azimuths) + "x" + std::to_string(opt.elevations);
  app.add_option("--clip", opt.clip, "clip to sample (default: the first)");
  app.add_option("--mesh", io.mesh, "mesh to bake (default: every mesh bound to the largest skin)");
  app.add_option("--frames", opt.frames, "frames sampled evenly over the clip")
      ->capture_default_str();
  app.add_option("--views", views, "azimuths x elevations")->capture_default_str();
  app.add_option("--texels", opt.texels, "a full view's size before cropping")
      ->capture_default_str();
  app.add_flag("--mirror", opt.mirror,
               "store azimuths 0..A/2 only: the others are mirrors of the views half a clip "
               "later (a walk); the report's mirror IoU says what that costs");
  addThreads(app, opt.threads);
  if (!parseArgs(app, argc, argv))
    return 0;
  b.files.finish();
  auto x = views.find('x');
  try {
    if (x == std::string::npos)
      throw std::invalid_argument(views);
    opt.azimuths = uint32_t(std::stoul(views.substr(0, x)));
    opt.elevations = uint32_t(std::stoul(views.substr(x + 1)));
  } catch (const std::exception &) {
    throw UsageError("--views expects AxE, e.g. 32x8, got '" + views + "'");
  }
  validated(opt);
  io.input = b.files.policy;
  crowd::ResourceGuard guard(b.files.limits, "crowdbake impostor " + b.input);
  auto t0 = std::chrono::steady_clock::now();
  crowd::Reporter reporter;
  reporter.quiet = b.quiet;
  crowd::Character character = crowd::importGltf(b.input, io, reporter);
  crowd::ImpostorBakeResult r = crowd::bakeImpostor(character, opt, reporter);
  crowd::pack::ImpostorPack pk;
  pk.impostor = std::move(r.impostor);
  pk.provenance =
      crowd::makeProvenance(character.sourceFiles, {{"command", "impostor"},
                                                    {"clip", opt.clip},
                                                    {"mesh", io.mesh},
                                                    {"frames", std::to_string(opt.frames)},
                                                    {"views", views},
                                                    {"texels", std::to_string(opt.texels)},
                                                    {"mirror", opt.mirror ? "yes" : "no"}});
  std::vector<uint8_t> bytes = crowd::pack::packBytes(pk);
  crowd::pack::writeFileAtomic(b.output, bytes);
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!b.report.empty()) {
    ordered_json j;
    j["command"] = "impostor";
    j["input"] = b.input;
    j["output"] = b.output;
    j["clip"] = pk.impostor.clip;
    j["frames"] = opt.frames;
    j["views"] = views;
    j["texels"] = opt.texels;
    j["atlas"] =
        std::to_string(pk.impostor.atlasWidth) + "x" + std::to_string(pk.impostor.atlasHeight);
    j["occupancy"] = r.occupancy;
    j["bytes_per_frame"] = r.bytesPerFrame;
    j["naive_bytes_per_frame"] = r.naiveBytesPerFrame;
    j["mirror_iou_min"] = r.mirrorIouMin;
    j["mirror_iou_mean"] = r.mirrorIouMean;
    auto t1 = std::chrono::steady_clock::now();
    crowd::ImpostorAccuracy acc = crowd::measureImpostor(character, pk.impostor, opt.threads);
    auto figures = [](const crowd::ImpostorAccuracy::Figures &f) {
      return ordered_json{{"iou_mean", f.iouMean},
                          {"iou_min", f.iouMin},
                          {"normal_error_mean_deg", f.normalMeanDeg},
                          {"normal_error_max_deg", f.normalMaxDeg},
                          {"uv_error_mean", f.uvMean},
                          {"uv_error_max", f.uvMax}};
    };
    j["accuracy"] = {
        {"frame", 0},
        {"at_views", figures(acc.atViews)},
        {"between_views", figures(acc.betweenViews)},
        {"worst",
         {{"azimuth_deg", acc.worstAzimuthDeg},
          {"elevation_deg", acc.worstElevationDeg},
          {"iou", acc.worstIou}}},
        {"time_s", std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count()}};
    j["pack_bytes"] = bytes.size();
    j["time_s"] = seconds;
    j["warnings"] = warningsJson(reporter);
    writeJson(b.report, j);
  }
  return 0;
}

} // namespace

int main(int argc, char **argv) {
  std::string command = argc > 1 ? argv[1] : "";
  try {
    if (command.empty()) {
      std::cerr << kTopHelp;
      return 2;
    }
    if (command == "--help" || command == "-h" || command == "help") {
      std::cout << kTopHelp;
      return 0;
    }
    // One function per command; each parses its own options (CLI11). The bakes read untrusted
    // input and run under the resource guard.
    const std::map<std::string, int (*)(int, char **)> commands = {
        {"build", cmdBuild},
        {"build-task", cmdBuildTask},
        {"samples", cmdSamples},
        {"anim", [](int c, char **v) { return cmdAnim(c, v, "anim"); }},
        {"lod", [](int c, char **v) { return cmdAnim(c, v, "lod"); }},
        {"impostor", cmdImpostor},
        {"outfits", cmdOutfits},
        {"inspect", cmdInspect},
        {"verify", cmdVerify},
        {"export", cmdExport},
    };
    auto it = commands.find(command);
    if (it == commands.end())
      throw UsageError("unknown command '" + command + "' (see crowdbake --help)");
    return it->second(argc, argv);
  } catch (const UsageError &e) {
    std::fprintf(stderr, "crowdbake: usage: %s\n", e.what());
    return 2;
  } catch (const std::exception &e) {
    std::string msg = e.what();
    for (char &ch : msg)
      if (ch == '\n')
        ch = ' ';
    std::fprintf(stderr, "crowdbake: error: %s\n", msg.c_str());
    return 1;
  }
}
