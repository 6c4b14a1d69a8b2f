// crowdbake impostor: one character's impostor job run alone (bake/src/build/single_job.cpp).
#include <cctype>
#include <stdexcept>
#include <string>

#include "commands.h"
#include "crowd/bake/impostor_bake.h"

namespace crowd::cli {

namespace {

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

} // namespace

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

} // namespace crowd::cli
