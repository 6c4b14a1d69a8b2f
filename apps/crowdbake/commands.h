// crowdbake sub-commands, each in its own file (<command>_command.cpp; inspect and verify in
// pack_commands.cpp).
#pragma once
#include "args.h"

namespace crowd::cli {

// Each parses its own options (CLI11) from argv[2..].
int cmdSamples(int argc, char **argv);
int cmdAnim(int argc, char **argv);
int cmdLod(int argc, char **argv);
int cmdImpostor(int argc, char **argv);
int cmdOutfits(int argc, char **argv);
int cmdBuild(int argc, char **argv);
int cmdBuildTask(int argc, char **argv); // a Slurm array task or collect job of a build
int cmdBuildJob(int argc, char **argv);  // one job of a local build, in a child process
int cmdInspect(int argc, char **argv);
int cmdVerify(int argc, char **argv);
int cmdExport(int argc, char **argv);
int cmdPose(int argc, char **argv);
int cmdCloth(int argc, char **argv);
int cmdTerrain(int argc, char **argv);
int cmdDiff(int argc, char **argv); // exits with the verdict (0..3), 4 when not compared
int cmdReport(int argc, char **argv);
int cmdCache(int argc, char **argv); // stats and gc of a build cache

} // namespace crowd::cli
