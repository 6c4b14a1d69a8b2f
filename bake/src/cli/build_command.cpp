// crowdbake build: character manifests and libraries through the job layer (CLI11 options).
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <unistd.h>

#include <CLI/CLI.hpp>

#include "args.h"
#include "crowd/bake/resource_guard.h"
#include "crowd/formats/error.h"
#include "commands.h"
#include "crowd/bake/build.h"

namespace crowd::cli {

namespace {

const char *const kDescription = R"(Builds characters into character packs: one pack per character holding everything the
player draws (animation, skin weights, mesh with continuous LOD on every sub-mesh, outfits and
their visibility, impostors for each listed (clip, outfit) pair).

INPUT is a character manifest, e.g.
  {"name": "soldier", "body": "Soldier.glb"}
  {"name": "villager", "body": "humanoid.glb",
   "outfits": {"dress": "outfit_dress.glb", "shirt": "outfit_shirt.glb"},
   "clips": ["walk", "run"], "anim": {"fps": 30, "precision": "float"},
   "lod": {"floor": 0.02, "poses": 16}, "visibility": {"rays": 24, "regions": "joint"},
   "impostor": {"clips": ["walk"], "outfits": ["dress"], "frames": 16, "texels": 128}}
(paths relative to the manifest; "lod": false turns LOD off; without "impostor", none), or a
library: {"characters": ["a.json", "b.json", {...inline manifest...}]}.

Every bake is a job keyed by its input bytes, settings and the baker version; a job whose key is
in the cache is not run again. A failing character fails alone: the others are written, the exit
code is 1 and the build report names it.)";

const char *const kExample = R"(
examples:
  crowdbake build soldier.json -o soldier.crowdpack
  crowdbake build library.json -o packs/ --jobs 8 --cache /shared/crowdbake-cache
)";

} // namespace

int cmdBuild(int argc, char **argv) {
  CLI::App app(kDescription, "crowdbake build");
  app.footer(kExample);
  BuildOptions o;
  bool quiet = false;
  app.add_option("INPUT", o.input, "character manifest or library (JSON)")->required();
  app.add_option("-o,--output", o.output,
                 "OUT.crowdpack for a character manifest; a folder for a library")
      ->required();
  app.add_option("--cache", o.cache,
                 "content cache folder (default: OUTDIR/.cache; one character: "
                 ".crowdbake-cache beside OUT); share it between builds and farm nodes");
  app.add_option("-j,--jobs", o.executor.workers, "jobs run at once (0: one per core)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1024));
  app.add_option("--report", o.report,
                 "build report JSON (default for a library: OUTDIR/build.report.json)");
  app.add_flag("-q,--quiet", quiet, "no progress on stderr");
  ResourceLimits limits;
  double maxFileMiB = double(o.files.maxFileBytes >> 20);
  app.add_option("--asset-root", o.files.assetRoot,
                 "files named by manifests and glTFs must resolve inside DIR (default: the "
                 "naming file's own folder)");
  app.add_option("--max-file-size", maxFileMiB, "largest input file read, in MiB")
      ->capture_default_str()
      ->check(CLI::Range(1.0, double(1 << 22)));
  app.add_option("--max-memory", limits.maxMemoryMiB,
                 "stop with an error past this resident memory, in MiB (0: 3/4 of RAM)")
      ->capture_default_str();
  app.add_option("--max-seconds", limits.maxSeconds, "stop with an error after this many seconds")
      ->capture_default_str();
  try {
    app.parse(argc - 1, argv + 1);
  } catch (const CLI::CallForHelp &) {
    std::cout << app.help();
    return 0;
  } catch (const CLI::ParseError &e) {
    throw UsageError(e.what());
  }
  o.executor.progress = quiet ? "none" : isatty(2) ? "bar" : "lines";
  o.files.maxFileBytes = uint64_t(maxFileMiB) << 20;
  try {
    o.files.validate();
  } catch (const Error &e) {
    throw UsageError(e.what());
  }
  ResourceGuard guard(limits, "crowdbake build " + o.input);
  BuildResult r = build(o);
  std::string report = o.report;
  if (report.empty() && std::filesystem::is_directory(o.output)) // a library's folder
    report = (std::filesystem::path(o.output) / "build.report.json").string();
  if (!report.empty())
    writeJson(report, r.report);
  if (!quiet) {
    for (const auto &c : r.characters) {
      if (c.failed)
        std::fprintf(stderr, "crowdbake: %s: FAILED: %s\n", c.name.c_str(), c.error.c_str());
      else
        std::fprintf(stderr, "crowdbake: %s: %zu jobs (%zu run, %zu cached), %.1f s, %llu bytes -> %s\n",
                     c.name.c_str(), c.jobs, c.run, c.cached, c.seconds,
                     (unsigned long long)c.bytes, c.pack.c_str());
    }
    const auto &j = r.report["jobs"];
    std::fprintf(stderr, "crowdbake: %zu jobs: %zu run, %zu cached, %zu failed; %.1f s%s%s\n",
                 j["total"].get<size_t>(), j["run"].get<size_t>(), j["cached"].get<size_t>(),
                 j["failed"].get<size_t>(), r.report["time_s"].get<double>(),
                 report.empty() ? "" : "; report ", report.c_str());
  }
  return r.failed() ? 1 : 0;
}

} // namespace crowd::cli
