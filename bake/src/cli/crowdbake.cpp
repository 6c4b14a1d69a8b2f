// crowdbake: the command-line front of the bake library. Sub-commands like git; every
// failure is one line on stderr and a non-zero exit (1 bad input or failed bake, 2 bad usage).
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <iostream>
#include <iterator>
#include <string>
#include <string_view>

#include "args.h"
#include "commands.h"
#include "crowd/bake/anim_bake.h"
#include "crowd/bake/impostor_bake.h"
#include "crowd/bake/lod_bake.h"
#include "crowd/bake/malloc_tuning.h"
#include "crowd/bake/provenance.h"
#include "crowd/formats/registry.h"
#include "crowd/samples/cloth_caches.h"
#include "crowd/samples/samples.h"

using namespace crowd::cli;

namespace {

const char *kTopHelp = R"(crowdbake: bake glTF characters into crowdpack files for real-time crowds

usage: crowdbake <command> [options]

commands:
  build     character manifests and libraries into character packs (jobs, content cache),
            locally or on a Slurm cluster
  samples   write the bundled sample characters (humanoid and three outfits) as .glb, and
            sample cloth caches (.pc2)
  anim      bake animation textures, skin weights and mesh from a glTF character
  lod       anim, plus continuous LOD: the mesh ordered for edge-collapse cuts at any vertex count
  outfits   body template + pre-fitted outfits: per outfit, which body sub-meshes are visible,
            hidden or partial over every frame, and outfit-specific copies of partial ones
  impostor  bake per-frame atlases of views (normals, region ids) for far-away characters
  inspect   list a pack's chunks, joints, clips, textures and sizes
  verify    check every offset, size, checksum and cross-reference of a pack
  export    write a pack's textures as images
  pose      write the mesh as the player draws it at given times (PLY, OBJ, PC2)
  cloth     a long cloth cache (PC2, MDD) of one garment into a loop in phase with a body clip
  terrain   an environment glTF into a height map, a walkable map and a shadow height map
            for a directional light (Tecchia, Loscos & Chrysanthou), with its mesh for drawing
  diff      a new pack against a golden one, chunk by chunk within tolerances (exit 0 same,
            1 warn, 2 fail, 3 different contents, 4 unreadable)
  report    build and bake reports as one HTML page: time, bytes and error per character and
            bake, with charts of error against bytes, triangles and memory

Run 'crowdbake <command> --help' for a command's options; 'crowdbake --version' names the
version, the toolchain it was built with and the pack and chunk versions it reads and writes.

example:
  crowdbake samples --out s && crowdbake anim s/humanoid.glb -o h.crowdpack --report r.json
)";

// What --mesh bakes when it is not given (ImportOptions::mesh).
const char *const kEveryMesh =
    "every skinned mesh with every skin it uses, merged into one skeleton, and the meshes "
    "rigidly parented to its joints";

const char *const kSamplesHelp = R"(Writes humanoid.glb, outfit_dress.glb, outfit_jumper_skirt.glb
and outfit_shirt_trousers.glb into DIR, the environment village.glb (for crowdbake terrain) with its agents' images village_behaviour.png and village_callbacks.png, and the cloth caches of the dress's garment "dress" (PC2,
30 fps, every vertex in the glTF's order; simulated, about 5 s): skirt_walk.pc2 and
skirt_run.pc2 (a loose skirt over 40 walk or run cycles), skirt_stiff.pc2 (a stiff one that
settles, 8 walk cycles) and noise.pc2 (never repeats). The output is deterministic: the same
bytes on every run.)";

const char *const kAnimHelp = R"(Samples every clip's joint matrices (global joint transform x
inverse bind) into one animation texture, and compresses every clip into local joint tracks on
its own keys; checks both against exact evaluation of the glTF with the player's interpolation
(at frames or samples, between them and at random times), and stores the one in fewer bytes
within the error budget (--store says which to keep), with skin weights (2 texels per vertex)
and the mesh; the report gives both and why one was kept.)";

const char *const kLodHelp = R"(Bakes what crowdbake anim bakes, with the mesh ordered for
continuous LOD: the full edge-collapse sequence down to a floor, so a renderer can draw any
vertex count v by taking each sub-mesh's first triangles (their count for v is stored) and
following indices through the collapse map until they are below v. Collapses run on a welded
mesh, cheapest quadric cost first, the cost the largest over the rest pose and poses sampled from
every clip, each as drawn (skinning-aware); a UV or normal seam vertex collapses only along its
seam, a boundary vertex only along its boundary; no cut has a degenerate triangle or one turned
more than 75 degrees from its full-detail normal. No new vertices. Non-manifold edges are cut
open (a vertex where several fans meet becomes one per fan); duplicate and zero-area triangles
are dropped; each repair is reported. Exact copies of a vertex (a mesh written without indices)
are welded; a flat-shaded mesh's copies that differ only by their normal are welded and drawn
with their face's normal (stored as zero). Where the LOD stops above the floor, a warning says
what blocks it.)";

const char *const kImpostorHelp = R"(For sampled frames of a clip, renders the character from
azimuths x elevations over the upper hemisphere with the deterministic rasterizer: object-space
normals (octahedral, BC5 blocks the GPU samples as stored), the region (sub-mesh) id + 1 (exact:
4 bits on the GPU where the ids fit, else a byte) and the UVs (BC5), each view cropped to its
silhouette and shelf-packed into one atlas per frame; the player keeps only each view's blocks
that hold covered texels, with a best impostor plane per view (fitted to the silhouette's depths,
tilted). The report gives what the blocks cost (normal degrees, UV distance, in texture texels
too) and the accuracy of the three-view blend the player draws, at and between the views. crowdplay draws the
pack for instances of this clip past the distance where a texel covers a pixel (scene file:
"impostor" in a pack). --texels auto sizes the views the other way round: from the distance where
the player should switch (--switch-distance, --screen, --fov), so no texel is stored that no
pixel shows.)";

int cmdSamples(int argc, char **argv) {
  CLI::App app(kSamplesHelp, "crowdbake samples");
  example(app, "crowdbake samples --out samples_out");
  std::string out;
  bool noCloth = false;
  app.add_option("--out", out, "folder to write the samples into")->required();
  app.add_flag("--no-cloth", noCloth, "skip the cloth caches (the characters only)");
  if (!parseArgs(app, argc, argv))
    return 0;
  crowd::samples::writeSamples(out);
  for (const auto &f : crowd::samples::kFiles)
    std::cout << out << "/" << f << "\n";
  std::cout << out << "/" << crowd::samples::kVillageFile << "\n";
  if (!noCloth) {
    crowd::samples::writeClothCaches(out);
    for (const auto &f : crowd::samples::kCacheFiles)
      std::cout << out << "/" << f << "\n";
  }
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
  crowd::LodOptions lodOpt;
  std::string clip, mesh;
  bool lodFlag = false;
  app.add_option("--clip", clip, "bake only this clip (default: every clip)");
  app.add_option("--mesh", mesh, std::string("bake only this mesh (default: ") + kEveryMesh + ")");
  addAnimOptions(app, opt);
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
                                  "the rest pose alone")
                       ->capture_default_str()
                       ->group(lodGroup);
  if (lodOption) {
    floorOpt->needs(lodOption);
    posesOpt->needs(lodOption);
  }
  if (!parseArgs(app, argc, argv))
    return 0;
  b.files.finish();
  validated(opt);
  validated(lodOpt);
  crowd::CharacterManifest m = b.manifest();
  m.mesh = mesh;
  if (!clip.empty())
    m.clips = {clip};
  m.anim = opt;
  m.lod = lodCommand || lodFlag;
  m.lodOptions = lodOpt;
  b.runJob(m, command, "mesh", opt.threads);
  return 0;
}

int cmdImpostor(int argc, char **argv) {
  CLI::App app(kImpostorHelp, "crowdbake impostor");
  example(app,
          "crowdbake impostor humanoid.glb -o walk_impostor.crowdpack --clip walk --frames 16");
  BakeArgs b;
  b.add(app);
  crowd::ImpostorOptions opt;
  std::string clip, mesh,
      views = std::to_string(opt.azimuths) + "x" + std::to_string(opt.elevations);
  app.add_option("--clip", clip, "clip to sample (default: the first)");
  app.add_option("--mesh", mesh, std::string("mesh to bake (default: ") + kEveryMesh + ")");
  app.add_option("--frames", opt.frames, "frames sampled evenly over the clip")
      ->capture_default_str();
  app.add_option("--views", views, "azimuths x elevations")->capture_default_str();
  std::string texels = std::to_string(opt.texels);
  app.add_option("--texels", texels,
                 "a full view's size before cropping, or auto: the fewest for which one texel "
                 "covers one pixel at --switch-distance (at most 512, with a warning)")
      ->capture_default_str();
  app.add_option("--switch-distance", opt.switchDistance,
                 "with --texels auto: where the player turns the character into an impostor, "
                 "model units from its centre");
  app.add_option("--screen", opt.screenHeight, "with --texels auto: the viewport's height, pixels")
      ->capture_default_str();
  app.add_option("--fov", opt.fovDegrees,
                 "with --texels auto: the camera's vertical field of view, degrees")
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
  if (texels == "auto") {
    if (!(opt.switchDistance > 0))
      throw UsageError("--texels auto needs --switch-distance (model units, > 0)");
  } else {
    if (opt.switchDistance != 0)
      throw UsageError("--switch-distance sizes the views only with --texels auto");
    try {
      size_t end = 0;
      opt.texels = uint32_t(std::stoul(texels, &end));
      if (end != texels.size() || !std::isdigit(static_cast<unsigned char>(texels[0])))
        throw std::invalid_argument(texels);
    } catch (const std::exception &) {
      throw UsageError("--texels expects a number of texels or auto, got '" + texels + "'");
    }
  }
  validated(opt);
  crowd::CharacterManifest m = b.manifest();
  m.mesh = mesh;
  m.impostor = opt;
  m.impostor.measure = !b.report.empty(); // figures only: the pack is the same without
  m.impostorPairs = {{clip, ""}};
  b.runJob(m, "impostor", "impostor", opt.threads);
  return 0;
}

} // namespace

int main(int argc, char **argv) {
  // One function per command; each parses its own options (CLI11). The bakes read untrusted
  // input and run under the resource guard; they (large arrays, long runs) also start again on
  // huge pages (useHugePages). The quick commands start once: a second start loads crowdbake and
  // its libraries again, tens of milliseconds.
  // A constant table: nothing to allocate (or throw) before the try below.
  struct Command {
    std::string_view name;
    int (*run)(int, char **);
    bool bake;
  };
  static constexpr Command kCommands[] = {
      {"build", cmdBuild, true},
      {"build-task", cmdBuildTask, true},
      {"samples", cmdSamples, false},
      {"anim", [](int c, char **v) { return cmdAnim(c, v, "anim"); }, true},
      {"lod", [](int c, char **v) { return cmdAnim(c, v, "lod"); }, true},
      {"impostor", cmdImpostor, true},
      {"outfits", cmdOutfits, true},
      {"inspect", cmdInspect, false},
      {"verify", cmdVerify, false},
      {"export", cmdExport, false},
      {"pose", cmdPose, false},
      {"cloth", cmdCloth, true},
      {"terrain", cmdTerrain, true},
      {"diff", cmdDiff, false},
      {"report", cmdReport, false},
  };
  const std::string_view command = argc > 1 ? argv[1] : "";
  const Command *const it = std::find_if(std::begin(kCommands), std::end(kCommands),
                                         [&](const Command &c) { return c.name == command; });
  const bool known = it != std::end(kCommands);
  if (known && it->bake)
    crowd::useHugePages(argv);
  crowd::keepFreedMemory();
  try {
    if (command.empty()) {
      std::cerr << kTopHelp;
      return 2;
    }
    if (command == "--help" || command == "-h" || command == "help") {
      std::cout << kTopHelp;
      return 0;
    }
    if (command == "--version") {
      std::cout << crowd::kBakerVersion << "\nbuilt with " << crowd::toolchain() << "\n"
                << crowd::pack::formatVersions() << "\n";
      return 0;
    }
    if (!known)
      throw UsageError("unknown command '" + std::string(command) + "' (see crowdbake --help)");
    return it->run(argc, argv);
  } catch (const std::exception &e) {
    printFailure(e);
    return dynamic_cast<const UsageError *>(&e) ? 2 : 1;
  }
}
