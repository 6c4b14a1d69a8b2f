// crowdbake sub-commands that live in their own files.
#pragma once
#include "args.h"

namespace crowd::cli {

extern const char *const kOutfitsHelp;
int cmdOutfits(const Args &a);
int cmdBuild(int argc, char **argv); // parses its own options (CLI11)
int cmdBuildTask(int argc, char **argv); // a Slurm array task or collect job of a build

} // namespace crowd::cli
