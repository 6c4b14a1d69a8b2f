// crowdbake build: character manifests and libraries through the job layer (CLI11 options).
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <unistd.h>

#include <CLI/CLI.hpp>

#include "args.h"
#include "commands.h"
#include "crowd/bake/build.h"
#include "crowd/bake/job_process.h"
#include "crowd/bake/resource_guard.h"
#include "crowd/bake/slurm.h"
#include "crowd/formats/error.h"

namespace crowd::cli {

namespace {

const char *const kBuildDescription =
    R"(Builds characters into character packs: one pack per character
holding everything the player draws (animation, skin weights, mesh with continuous LOD on every
sub-mesh, outfits and their visibility, impostors for each listed (clip, outfit) pair).

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
in the cache is not run again. Each job runs in a process of its own, bounded by --job-max-seconds
and --job-max-memory (a manifest's "limits": {"seconds": S, "memory_mib": M} sets them for its
character). A failing character fails alone, whether its job failed, ran past a limit, crashed
or was killed (a job killed from outside runs once more): the others are written, the exit code
is 1 and the build report names it. Ctrl-C (or SIGTERM) stops the build: what finished stays in
the cache, no file is left half-written, and the next build goes on from there (exit code 130).
The build as a whole has no time limit unless --max-seconds gives one.)";

const char *const kBuildExample = R"(
On a Slurm cluster (--slurm), the same jobs run as job arrays sharing the cache folder, which
must be on a file system every node sees, like crowdbake itself and the inputs; a last collect
job writes the packs and the report. --emit-slurm DIR only writes the scripts (DIR/submit.sh
submits them).

With --scene SCENE.json (a crowdplay scene whose packs are this build's outputs, NAME.crowdpack
for the character NAME), only what the scene draws is built: its characters, the clips and
outfits its instances use, and impostors for the listed pairs that some instance shows past the
switch distance (from any point of the camera's path). The report's "scene" says what was left
out and why, and what that saved against the full library when the cache holds its parts.

examples:
  crowdbake build soldier.json -o soldier.crowdpack
  crowdbake build library.json -o packs/ --jobs 8 --cache /shared/crowdbake-cache
  crowdbake build library.json -o /shared/packs --slurm --partition bake --cpus-per-task 8
  crowdbake build library.json -o packs/ --scene market.json --screen 1080
)";

const char *const kBuildJobHelp = R"(usage: crowdbake build-job SPEC

Run by 'crowdbake build' in a child process per job: SPEC (JSON, written by the build) names the
library, the character's entry, the job, its key, the cache and the job's limits. The job's part
goes into the cache; errors are one line on stderr.
)";

const char *const kBuildTaskHelp = R"(usage: crowdbake build-task PLAN STAGE TASK
       crowdbake build-task PLAN collect

Run by the sbatch scripts that 'crowdbake build --slurm' and '--emit-slurm' write: array task
TASK of stage STAGE of PLAN (their plan.json) runs its jobs into the shared cache, recording a
failed job there and going on; 'collect' writes the packs and the build report from the cache.
)";

size_t parseIndex(const std::string &text, const char *what) {
  size_t used = 0;
  int value = -1;
  try {
    value = std::stoi(text, &used);
  } catch (const std::exception &) {
  }
  if (used != text.size() || value < 0)
    throw UsageError(std::string(what) + ": '" + text + "' is not a number >= 0");
  return size_t(value);
}

// One line per character and the totals, from a build report; `quiet`: the failures alone (a
// quiet build that fails still says why).
void printSummary(const nlohmann::ordered_json &r, const std::string &reportPath, bool quiet) {
  for (const auto &c : r["characters"]) {
    const std::string name = c["name"];
    if (c["status"] != "ok") {
      std::fprintf(stderr, "crowdbake: %s: FAILED: %s\n", name.c_str(),
                   c["error"].get<std::string>().c_str());
      continue;
    }
    if (quiet)
      continue;
    std::fprintf(stderr,
                 "crowdbake: %s: %zu jobs (%zu run, %zu cached), %.1f s, %llu bytes -> %s\n",
                 name.c_str(), c["jobs"].size(), c["jobs_run"].get<size_t>(),
                 c["jobs_cached"].get<size_t>(), c["bake_s"].get<double>(),
                 c["pack_bytes"].get<unsigned long long>(), c["pack"].get<std::string>().c_str());
  }
  if (quiet)
    return;
  if (r.contains("scene")) {
    const auto &s = r["scene"];
    std::string leftOut;
    for (const auto &c : s["characters"])
      if (c.contains("left_out"))
        leftOut.append(leftOut.empty() ? "" : ", ").append(c["name"].get<std::string>());
    std::fprintf(stderr, "crowdbake: scene %s: %zu of the full build's %zu jobs; left out: %s\n",
                 s["file"].get<std::string>().c_str(), s["jobs"].get<size_t>(),
                 s["full_build_jobs"].get<size_t>(), leftOut.empty() ? "none" : leftOut.c_str());
    if (s["saved"].is_object())
      std::fprintf(stderr,
                   "crowdbake: scene build against the full build: %.1f s of %.1f s of bake and "
                   "%lld of %llu pack bytes saved\n",
                   s["saved"]["bake_s"].get<double>(), s["full_build"]["bake_s"].get<double>(),
                   s["saved"]["pack_bytes"].get<long long>(),
                   s["full_build"]["pack_bytes"].get<unsigned long long>());
    else
      std::fprintf(stderr, "crowdbake: %s\n", s["saved"].get<std::string>().c_str());
  }
  const auto &j = r["jobs"];
  std::fprintf(stderr, "crowdbake: %zu jobs: %zu run, %zu cached, %zu failed; %.1f s%s%s\n",
               j["total"].get<size_t>(), j["run"].get<size_t>(), j["cached"].get<size_t>(),
               j["failed"].get<size_t>(), r["time_s"].get<double>(),
               reportPath.empty() ? "" : "; report ", reportPath.c_str());
}

// Writes the Slurm scripts and, with `submit`, runs them and waits for the collect job.
// The guard bounds the planning here, not the wait for the cluster.
int slurmBuild(const BuildOptions &o, const SlurmOptions &slurm, const ResourceLimits &limits,
               bool submit, bool quiet) {
  namespace fs = std::filesystem;
  std::string summary;
  {
    ResourceGuard guard(limits, "crowdbake build " + o.input);
    summary = writeSlurmScripts(o, slurm);
  }
  if (!quiet)
    std::fprintf(stderr, "%s", summary.c_str());
  if (!submit)
    return 0;
  const nlohmann::ordered_json report = submitSlurmBuild(o, slurm, quiet);
  const fs::path folder = fs::absolute(slurm.folder);
  if (!quiet)
    std::fprintf(stderr,
                 "crowdbake: on Slurm, 'cached' counts the parts the array tasks wrote "
                 "(their logs: %s/logs)\n",
                 folder.c_str());
  printSummary(report, o.report, quiet);
  return report["characters_failed"].get<size_t>() > 0 ? 1 : 0;
}

} // namespace

int cmdBuild(int argc, char **argv) {
  CLI::App app(kBuildDescription, "crowdbake build");
  app.footer(kBuildExample);
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
  SlurmOptions slurm;
  bool useSlurm = false;
  app.add_flag("--slurm", useSlurm,
               "run the jobs on a Slurm cluster (sbatch job arrays) and wait for the packs");
  app.add_option("--emit-slurm", slurm.folder,
                 "write the plan and sbatch scripts into DIR (DIR/submit.sh submits them); "
                 "with --slurm, where they go (default: OUTDIR/.slurm, or OUT.slurm)");
  app.add_option("--partition", slurm.partition, "Slurm partition (default: the cluster's)");
  app.add_option("--jobs-per-task", slurm.jobsPerTask,
                 "jobs each Slurm array task runs (Slurm adds about a second per task)")
      ->capture_default_str();
  app.add_option("--cpus-per-task", slurm.cpusPerTask, "Slurm CPUs per task: a job's threads")
      ->capture_default_str();
  app.add_option("--max-array-size", slurm.maxArraySize,
                 "tasks per Slurm job array; a stage of more is several arrays (default: the "
                 "cluster's MaxArraySize, from scontrol show config, else 1001)");
  auto *scene = app.add_option("--scene", o.scene.scene,
                               "build only what this crowdplay scene draws (see below)")
                    ->group("Scene builds");
  app.add_option("--screen", o.scene.screenHeight,
                 "pixels: the height of the viewport the scene is drawn at")
      ->capture_default_str()
      ->needs(scene)
      ->group("Scene builds");
  app.add_option("--switch-distance", o.scene.switchDistance,
                 "scene units: where characters turn into impostors; their texels are chosen "
                 "so that one covers one pixel there (default: where the manifest's texels do)")
      ->needs(scene)
      ->group("Scene builds");
  app.add_option("--job-max-seconds", o.jobLimits.maxSeconds,
                 "kill a job past this many seconds; it fails alone (0: no limit)")
      ->capture_default_str()
      ->group("Per-job limits");
  app.add_option("--job-max-memory", o.jobLimits.maxMemoryMiB,
                 "stop a job past this resident memory, in MiB; it fails alone (0: no limit)")
      ->capture_default_str()
      ->group("Per-job limits");
  InputArgs files;
  // The build as a whole runs as long as its jobs need: each has limits of its own.
  files.limits.maxSeconds = 0;
  files.add(app);
  if (!parseArgs(app, argc, argv))
    return 0;
  files.finish();
  validated(o.jobLimits);
  validated(o.scene);
  o.files = files.policy;
  o.executor.progress = quiet ? "none" : isatty(2) ? "bar" : "lines";
  namespace fs = std::filesystem;
  const bool library = fs::path(o.output).extension() != ".crowdpack";
  const bool onSlurm = useSlurm || !slurm.folder.empty();
  if (onSlurm && slurm.folder.empty())
    slurm.folder = library ? (fs::path(o.output) / ".slurm").string() : o.output + ".slurm";
  if (o.report.empty())
    o.report = library   ? (fs::path(o.output) / "build.report.json").string()
               : onSlurm ? (fs::path(slurm.folder) / "build.report.json").string()
                         : "";
  if (onSlurm) {
    slurm.crowdbake = fs::read_symlink("/proc/self/exe").string();
    try {
      slurm.validate();
    } catch (const Error &e) {
      throw UsageError(e.what());
    }
  }
  if (onSlurm)
    return slurmBuild(o, slurm, files.limits, useSlurm, quiet);
  ResourceGuard guard(files.limits, "crowdbake build " + o.input,
                      "the packs written before it kept, finished jobs in the cache");
  o.jobExecutable = fs::read_symlink("/proc/self/exe").string();
  catchInterrupts();
  BuildResult r = build(o);
  printSummary(r.report, o.report, quiet); // first: a report not written must not hide a failure
  if (!o.report.empty())
    writeJson(o.report, r.report);
  if (r.interrupted) {
    std::fprintf(stderr,
                 "crowdbake: interrupted: %zu of %zu jobs are in the cache; build again "
                 "to go on from them\n",
                 r.report["jobs"]["total"].get<size_t>() - r.report["jobs"]["failed"].get<size_t>(),
                 r.report["jobs"]["total"].get<size_t>());
    return 130;
  }
  return r.failed() ? 1 : 0;
}

int cmdBuildJob(int argc, char **argv) {
  if (argc == 3 && (std::string(argv[2]) == "--help" || std::string(argv[2]) == "-h")) {
    std::cout << kBuildJobHelp;
    return 0;
  }
  if (argc != 3)
    throw UsageError("crowdbake build-job SPEC (run by crowdbake build; see --help)");
  runJobSpec(JobSpec::parse(argv[2]));
  return 0;
}

int cmdBuildTask(int argc, char **argv) {
  if (argc == 3 && (std::string(argv[2]) == "--help" || std::string(argv[2]) == "-h")) {
    std::cout << kBuildTaskHelp;
    return 0;
  }
  if (argc != 4 && argc != 5)
    throw UsageError("crowdbake build-task PLAN STAGE TASK | PLAN collect (see --help)");
  const std::string plan = argv[2], what = argv[3];
  if (what == "collect" && argc == 4) {
    const BuildOptions o = slurmCollectOptions(plan);
    BuildResult r = build(o);
    writeJson(o.report, r.report);
    printSummary(r.report, o.report, false);
    return r.failed() ? 1 : 0;
  }
  if (argc != 5)
    throw UsageError("crowdbake build-task PLAN STAGE TASK | PLAN collect (see --help)");
  runSlurmTask(plan, parseIndex(what, "STAGE"), parseIndex(argv[4], "TASK"));
  return 0;
}

} // namespace crowd::cli
