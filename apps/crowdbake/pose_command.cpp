// crowdbake pose: the mesh exactly as the player draws it at given times, as PLY, glTF, OBJ or
// PC2.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "commands.h"
#include "crowd/bake/mesh_files.h"
#include "crowd/support/point_cache.h"
#include "crowd/formats/character_pack.h"
#include "crowd/formats/container.h"
#include "crowd/runtime/pose.h"

namespace crowd::cli {

namespace {

namespace fs = std::filesystem;

const char *const kPoseHelp = R"(Writes the mesh exactly as crowdplay draws it at a time of a clip:
the outfit's sub-meshes at the LOD cut, skinned from the pack's animation and skin textures by
the CPU mirror of the player's vertex shader (the same texel fetch, frame blend and single
precision); a pack of joint tracks alone (crowdbake anim --store tracks) by the CPU mirror of
the player's palette pass. A time past the clip's end wraps for a looping clip and clamps
otherwise, with a warning; a pack without clips writes the bind pose. A garment with a cloth loop over the clip
(crowdbake cloth) plays its loop, whose cycles count on past the clip's end: the time is not
wrapped for it. Formats: PLY, binary glTF (.glb: a static
mesh, unit normals), OBJ and PC2. --times writes OUT_0001.EXT, ... per time,
or with -o OUT.pc2 one point cache (evenly spaced times; start and spacing in seconds).
Times count from the clip's first frame: source time = start_time (crowdbake inspect) + t.
A PLY also gives per vertex where it came from (the pack's SRCV chunk): source_file (0: the
character's glTF, k: its k-th outfit's), source_node, source_mesh, source_primitive and
source_vertex, the glTF indices the vertex was read from (-1: made by the bake, or unknown).)";

std::vector<float> parseTimes(const std::string &text) {
  std::vector<float> times;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    size_t used = 0;
    float t = 0;
    try {
      t = std::stof(item, &used);
    } catch (const std::exception &) {
      used = 0;
    }
    if (used == 0 || used != item.size())
      throw UsageError("--times: '" + item + "' is not a number");
    times.push_back(t);
  }
  return times;
}

// Every time must be a finite number of seconds >= 0; the times past the clip's end get one
// warning (the player wraps a looping clip and clamps another), not one line each.
void checkTimes(const pack::Clip *clip, const std::vector<float> &times, bool quiet) {
  for (float t : times)
    if (!std::isfinite(t) || t < 0) {
      char text[64];
      std::snprintf(text, sizeof text, "time %g: must be a finite number of seconds >= 0", t);
      throw UsageError(text);
    }
  if (!clip || clip->frameCount < 2 || quiet)
    return;
  const float duration = float(clip->frameCount - 1) / clip->fps;
  const auto isPast = [&](float x) { return x > duration; };
  const auto firstPast = std::find_if(times.begin(), times.end(), isPast);
  if (firstPast == times.end())
    return;
  const auto past = std::count_if(firstPast, times.end(), isPast);
  const float t = *firstPast;
  const float shown = clip->loop ? std::fmod(t, duration) : duration;
  const char *rule = clip->loop ? "wraps" : "clamps";
  if (past == 1)
    std::fprintf(
        stderr,
        "crowdbake: warning: time %g s is past clip '%s' (%g s): the player %s it to %g s\n", t,
        clip->name.c_str(), duration, rule, shown);
  else
    std::fprintf(stderr,
                 "crowdbake: warning: %td of %zu times are past clip '%s' (%g s): the player %s "
                 "them (the first, %g s, to %g s)\n",
                 past, times.size(), clip->name.c_str(), duration, rule, t, shown);
}

std::string numbered(const std::string &out, size_t k) {
  const fs::path p(out);
  char n[32];
  std::snprintf(n, sizeof n, "_%04zu", k + 1);
  return (p.parent_path() / (p.stem().string() + n + p.extension().string())).string();
}

} // namespace

int cmdPose(int argc, char **argv) {
  CLI::App app(kPoseHelp, "crowdbake pose");
  example(app, "crowdbake pose humanoid.crowdpack --clip walk --time 0.4 -o walk.ply");
  std::string path, output, timesText;
  runtime::PoseOptions opt;
  float time = 0;
  bool ascii = false, quiet = false;
  app.add_option("PACK", path, "a .crowdpack file")->required();
  app.add_option("-o,--output", output, "OUT.ply, OUT.glb, OUT.obj or OUT.pc2 (written atomically)")
      ->required();
  app.add_option("--clip", opt.clip, "clip (default: the first)");
  auto *timeOpt =
      app.add_option("--time", time, "seconds from the clip's first frame")->capture_default_str();
  app.add_option("--times", timesText, "T1,T2,...: several times, one file each (or one .pc2)")
      ->excludes(timeOpt);
  app.add_option("--outfit", opt.outfit, "outfit of a clothed pack (default: the first)");
  app.add_option("--lod", opt.lodVertices, "draw the LOD cut at this many vertices (0: full)")
      ->capture_default_str();
  app.add_flag("--ascii", ascii, "ASCII PLY instead of binary little-endian");
  app.add_flag("-q,--quiet", quiet, "no warnings on stderr");
  if (!parseArgs(app, argc, argv))
    return 0;
  const std::string ext = fs::path(output).extension().string();
  if (ext != ".ply" && ext != ".glb" && ext != ".obj" && ext != ".pc2")
    throw UsageError("-o: expected a .ply, .glb, .obj or .pc2 file, got '" + output + "'");
  const std::vector<float> times =
      timesText.empty() ? std::vector<float>{time} : parseTimes(timesText);
  const fs::path folder = fs::path(output).parent_path();
  std::error_code ec;
  if (!folder.empty() && !fs::is_directory(folder, ec))
    throw Error(output + ": the folder " + folder.string() + " does not exist");

  const pack::CharacterPack character = pack::loadCharacterPack(pack::Reader::open(path));
  const pack::AnimationPack &pack = character.body;
  const runtime::PoseMesh mesh = runtime::poseMesh(pack, opt, character.cloths);
  checkTimes(mesh.clip, times, quiet);
  std::vector<pack::VertexSource> sources(mesh.vertices.size());
  if (pack.sources) {
    const auto all = pack.sources->expand();
    for (size_t k = 0; k < mesh.vertices.size(); ++k)
      sources[k] = all[mesh.vertices[k]];
  }
  std::vector<std::vector<glm::vec3>> samples;
  std::vector<glm::vec3> positions, normals;
  for (size_t k = 0; k < times.size(); ++k) {
    runtime::poseAt(pack, mesh, times[k], positions, normals);
    if (ext == ".pc2") {
      samples.push_back(positions);
      continue;
    }
    const std::string file = times.size() == 1 ? output : numbered(output, k);
    pack::writeFileAtomic(file, ext == ".ply"
                                    ? plyBytes(positions, normals, mesh.indices, sources, ascii)
                                : ext == ".glb" ? glbBytes(positions, normals, mesh.indices)
                                                : objBytes(positions, normals, mesh.indices));
  }
  if (ext == ".pc2") {
    const float spacing =
        times.size() > 1 ? (times.back() - times.front()) / float(times.size() - 1) : 0;
    for (size_t k = 1; k < times.size(); ++k)
      if (std::abs(times[k] - (times.front() + spacing * float(k))) >
          1e-4f * std::max(1.0f, spacing))
        throw UsageError("--times: a .pc2 stores evenly spaced samples; " + timesText + " is not");
    pack::writeFileAtomic(
        output, encodePointCache(PointCacheFormat::Pc2, samples, 0.0, times.front(), spacing));
  }
  return 0;
}

} // namespace crowd::cli
