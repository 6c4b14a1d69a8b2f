// crowdbake outfits: a body template and pre-fitted outfits into one clothed-crowd pack.
#include <filesystem>

#include "args.h"
#include "commands.h"
#include "crowd/bake/outfit_bake.h"

namespace crowd::cli {

namespace {

const char *const kOutfitsDescription =
    R"(The "tagged" method of clothed crowds: the body template keeps
its sub-meshes (one per material); each outfit's garments, skinned to the same skeleton (joints
matched by name), are added. For each outfit and body sub-mesh the bake decides, over every
frame of every clip, whether the sub-mesh is visible, hidden (never drawn with that outfit) or
partial (drawn through an outfit-specific copy holding only its visible faces). A body face is
hidden only if, in every tested frame, rays from points on it over its whole outward hemisphere
all hit the garments or the body. Alpha-masked or blended garments never hide anything.
crowdplay draws the pack with an outfit per character (scene file: "outfit").)";

} // namespace

int cmdOutfits(int argc, char **argv) {
  CLI::App app(kOutfitsDescription, "crowdbake outfits");
  example(app, "crowdbake outfits humanoid.glb --outfit outfit_dress.glb --outfit "
               "outfit_jumper_skirt.glb -o clothed.crowdpack --check 4 --report clothed.json");
  BakeArgs b;
  b.add(app);
  OutfitOptions opt;
  auto &vis = opt.visibility;
  std::vector<std::string> outfitArgs;
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
  app.add_option("--check", opt.check,
                 "after baking, test that no hole opens: render every outfit naively and culled "
                 "from the 32x8 impostor views and 16 player-like views (128x128 texels) at every "
                 "K-th frame of every clip and compare pixels (0: no check); a differing pixel "
                 "fails the bake, naming the body parts, the frame and the view. Sampled: a hole "
                 "between checked frames or texel centres goes unseen")
      ->capture_default_str();
  AnimBakeOptions anim;
  addAnimOptions(app, anim);
  addThreads(app, vis.threads);
  if (!parseArgs(app, argc, argv))
    return 0;
  b.files.finish();
  vis.ground = !noGround;
  anim.threads = vis.threads;
  opt.setAnimation(anim);
  validated(opt);
  CharacterManifest m = b.manifest();
  for (const auto &arg : outfitArgs) {
    auto [name, file] = outfitNameAndFile(arg);
    for (const auto &o : m.outfits)
      if (o.first == name)
        throw UsageError("two outfits are named '" + name + "' (use --outfit NAME=FILE)");
    m.outfits.emplace_back(name, file);
  }
  m.anim = anim;
  m.outfitOptions = opt;
  m.lod = false;
  b.runJob(m, "outfits", "mesh", vis.threads);
  return 0;
}

} // namespace crowd::cli
