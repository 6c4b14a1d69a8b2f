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
  cache     a build cache: what it holds (stats), trimmed to a size (gc), safe while builds
            use it

Run 'crowdbake <command> --help' for a command's options; 'crowdbake --version' names the
version, the toolchain it was built with and the pack and chunk versions it reads and writes.

example:
  crowdbake samples --out s && crowdbake anim s/humanoid.glb -o h.crowdpack --report r.json
)";

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
      {"build-job", cmdBuildJob, true},
      {"samples", cmdSamples, false},
      {"anim", cmdAnim, true},
      {"lod", cmdLod, true},
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
      {"cache", cmdCache, false},
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
