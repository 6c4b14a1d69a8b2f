// A library build on a Slurm cluster: the same jobs as a local build, run by job arrays that
// share the content cache. Jobs are staged by dependency depth (stage 0: meshes and impostors,
// stage 1: the links); each stage is one array (or several, past the cluster's MaxArraySize)
// whose tasks run several jobs each (Slurm adds about a second per task), started afterok of
// the stage before; a last collect job writes the packs and the build report from the cache,
// exactly as a local build would. A task plans only the characters of its jobs (job_process.h),
// not the library. Per-job limits become the tasks' --time and --mem.
//
// A job that fails in a task is recorded in the cache and the task goes on, so one bad
// character never stops the arrays; the collect step reports it. A task exits non-zero only
// when it cannot work at all (inputs changed since submission, cache not writable), and then
// afterok cancels what follows.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

#include "crowd/bake/build.h"

namespace crowd {

struct SlurmOptions {
  std::string folder;    // where the plan, the sbatch scripts and the task logs go
  std::string partition; // "" : the cluster's default partition
  int jobsPerTask = 4;   // jobs each array task runs, one after another
  int cpusPerTask = 4;   // Slurm --cpus-per-task; a job's bake threads
  std::string crowdbake; // the executable the tasks run: a path every node can reach
  // Tasks per job array; a stage of more is several arrays. 0: the cluster's MaxArraySize.
  int maxArraySize = 0;
  void validate() const; // throws naming the field
};

// The cluster's MaxArraySize (scontrol show config), or Slurm's default 1001 where it cannot
// be read.
int clusterMaxArraySize();

// Writes FOLDER/plan.json, one sbatch script per stage, collect.sbatch and submit.sh (which
// submits them in order with afterok dependencies; with WAIT=1 it waits for the collect job
// and exits with its status). Returns a summary line per script.
std::string writeSlurmScripts(const BuildOptions &build, const SlurmOptions &slurm);

// Runs the scripts writeSlurmScripts wrote (FOLDER/submit.sh, WAIT=1) and waits for the collect
// job; the scripts' messages (an array's id, sbatch's errors) pass to stderr unless `quiet`.
// Returns the build report the collect job wrote (build.report). Throws naming what failed:
// sbatch not runnable, or no report written (with the script's last message and the logs).
nlohmann::ordered_json submitSlurmBuild(const BuildOptions &build, const SlurmOptions &slurm,
                                        bool quiet);

// Inside an array task: runs task `task` of stage `stage` of the plan, one line per job on
// stdout (the task's log).
void runSlurmTask(const std::string &plan, int stage, int task);

// The collect job's options: the plan's build, with its parts from the cache and the failures
// that tasks recorded there (run it with build()).
BuildOptions slurmCollectOptions(const std::string &plan);

} // namespace crowd
