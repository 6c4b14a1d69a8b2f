// crowdbake anim and lod: one character's mesh job run alone (bake/src/build/single_job.cpp),
// the animation with or without continuous LOD.
#include <string>

#include "commands.h"
#include "crowd/bake/anim_bake.h"
#include "crowd/bake/lod_bake.h"

namespace crowd::cli {

namespace {

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
every clip, each as drawn (skinning-aware); a UV seam vertex collapses only along its seam, a
boundary vertex only along its boundary, a hard edge's (a normal seam's) also across it where the
drawn colour changes by no more than --seam-budget; no cut has a degenerate triangle or one turned
more than 75 degrees from its full-detail normal. No new vertices. Non-manifold edges are cut
open (a vertex where several fans meet becomes one per fan); duplicate and zero-area triangles
are dropped; each repair is reported. Exact copies of a vertex (a mesh written without indices)
are welded; a flat-shaded mesh's copies that differ only by their normal are welded and drawn
with their face's normal (stored as zero). An untextured sub-mesh draws its material's colour
whatever its UVs, so there UVs part no copies. Where the LOD stops above the floor, a warning says
what blocks it.)";

} // namespace

namespace {

int animOrLod(int argc, char **argv, const std::string &command) {
  const bool lodCommand = command == "lod";
  CLI::App app(lodCommand ? kLodHelp : kAnimHelp, "crowdbake " + command);
  example(app, lodCommand
                   ? "crowdbake lod humanoid.glb -o humanoid.crowdpack --report r.json"
                   : "crowdbake anim humanoid.glb -o humanoid.crowdpack --report r.json");
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
  auto *seamOpt =
      app.add_option("--seam-budget", lodOpt.seamBudget,
                     "the most a collapse that closes a hard edge (a normal seam) may change the "
                     "drawn colour, 8-bit RGB distance under the player's light at its worst "
                     "direction, against the full-detail mesh; 0: hard edges hold. UV seams of "
                     "a textured sub-mesh always hold")
          ->capture_default_str()
          ->group(lodGroup);
  if (lodOption) {
    floorOpt->needs(lodOption);
    posesOpt->needs(lodOption);
    seamOpt->needs(lodOption);
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

} // namespace

int cmdAnim(int argc, char **argv) { return animOrLod(argc, argv, "anim"); }
int cmdLod(int argc, char **argv) { return animOrLod(argc, argv, "lod"); }

} // namespace crowd::cli
