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
#include "crowd/bake/malloc_tuning.h"
#include "crowd/bake/provenance.h"
#include "crowd/formats/registry.h"

using namespace crowd::cli;

namespace {

// The commands, in the order the help lists them: the one list (README.md's table and
// docs/commands.md name the same ones, ctest `commands_agree`). A constant table: nothing to
// allocate (or throw) before main's try. A command without a summary is internal (the farm's).
struct Command {
  std::string_view name;
  int (*run)(int, char **);
  bool bake;
  std::string_view summary;
};
constexpr Command kCommands[] = {
    {"build", cmdBuild, true,
     "character manifests and libraries into character packs (jobs, content cache), locally or "
     "on a Slurm cluster"},
    {"build-task", cmdBuildTask, true, ""},
    {"build-job", cmdBuildJob, true, ""},
    {"samples", cmdSamples, false,
     "write the bundled sample characters (humanoid and three outfits) and the village "
     "environment as .glb, and sample cloth caches (.pc2)"},
    {"anim", cmdAnim, true,
     "animation (joint tracks or a texture), skin weights and mesh from a glTF character"},
    {"lod", cmdLod, true,
     "anim plus continuous LOD: the mesh in edge-collapse order, cut at any vertex count"},
    {"outfits", cmdOutfits, true,
     "body template + pre-fitted outfits: per outfit, which body sub-meshes are visible, hidden "
     "or partial over every frame, and outfit-specific copies of partial ones"},
    {"impostor", cmdImpostor, true,
     "bake per-frame atlases of views (normals, region ids) for far-away characters"},
    {"inspect", cmdInspect, false, "list a pack's chunks, joints, clips, textures and sizes"},
    {"verify", cmdVerify, false,
     "check every offset, size, checksum and cross-reference of a pack"},
    {"export", cmdExport, false,
     "write a pack's images (--images) or the character as a binary glTF (--gltf)"},
    {"pose", cmdPose, false,
     "write the mesh as the player draws it at given times (PLY, OBJ, GLB, PC2)"},
    {"cloth", cmdCloth, true,
     "a long cloth cache (PC2, MDD) of one garment into a loop in phase with a body clip"},
    {"terrain", cmdTerrain, true,
     "an environment glTF into a height map, a walkable map and a shadow height map for a "
     "directional light (Tecchia, Loscos & Chrysanthou), with its mesh for drawing"},
    {"diff", cmdDiff, false,
     "a new pack against a golden one, chunk by chunk within tolerances (exit 0 same, 1 warn, "
     "2 fail, 3 different contents, 4 unreadable)"},
    {"report", cmdReport, false,
     "build and bake reports as one HTML page: time, bytes and error per character and bake, "
     "with charts of error against bytes, triangles and memory"},
    {"cache", cmdCache, false,
     "a build cache: its contents (stats), trimmed to a size (gc), safe beside running builds"},
};

// The top-level help: each public command and its summary, wrapped at 96 columns.
std::string topHelp() {
  std::string out = "crowdbake: bake glTF characters into crowdpack files for real-time crowds\n\n"
                    "usage: crowdbake <command> [options]\n\ncommands:\n";
  constexpr size_t kIndent = 12, kWidth = 96;
  for (const Command &c : kCommands) {
    if (c.summary.empty())
      continue;
    std::string line = "  " + std::string(c.name);
    line.resize(kIndent, ' ');
    for (size_t at = 0; at < c.summary.size();) {
      const size_t space = std::min(c.summary.find(' ', at), c.summary.size());
      const std::string_view word = c.summary.substr(at, space - at);
      if (line.size() > kIndent && line.size() + 1 + word.size() > kWidth) {
        out += line + "\n";
        line.assign(kIndent, ' ');
      }
      if (line.size() > kIndent)
        line += ' ';
      line += word;
      at = space + 1;
    }
    out += line + "\n";
  }
  return out + R"(
Run 'crowdbake <command> --help' for a command's options; 'crowdbake --version' names the
version, the toolchain it was built with and the pack and chunk versions it reads and writes.

example:
  crowdbake samples --out s && crowdbake anim s/humanoid.glb -o h.crowdpack --report r.json
)";
}

} // namespace

int main(int argc, char **argv) {
  // One function per command; each parses its own options (CLI11). The bakes read untrusted
  // input and run under the resource guard; they (large arrays, long runs) also start again on
  // huge pages (useHugePages). The quick commands start once: a second start loads crowdbake and
  // its libraries again, tens of milliseconds.
  const std::string_view command = argc > 1 ? argv[1] : "";
  const Command *const it = std::find_if(std::begin(kCommands), std::end(kCommands),
                                         [&](const Command &c) { return c.name == command; });
  const bool known = it != std::end(kCommands);
  if (known && it->bake)
    crowd::useHugePages(argv);
  crowd::keepFreedMemory();
  try {
    if (command.empty()) {
      std::cerr << topHelp();
      return 2;
    }
    if (command == "--help" || command == "-h" || command == "help") {
      std::cout << topHelp();
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
