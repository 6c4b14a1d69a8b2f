#include "crowd/bake/slurm.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>

#include "build_inputs_json.h"
#include "crowd/bake/cache_admin.h"
#include "crowd/bake/content_cache.h"
#include "crowd/bake/executor.h"
#include "crowd/bake/job_process.h"
#include "crowd/bake/provenance.h"
#include "crowd/formats/container.h"
#include "crowd/formats/error.h"

namespace crowd {

namespace fs = std::filesystem;
using nlohmann::ordered_json;

namespace {

std::string absolute(const std::string &path) {
  return path.empty() ? path : fs::absolute(path).lexically_normal().string();
}

// Single quotes for a POSIX shell.
std::string quoted(const std::string &s) {
  std::string q = "'";
  for (char c : s)
    q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

void writeText(const std::string &path, const std::string &text, bool executable = false) {
  pack::writeFileAtomic(path, {reinterpret_cast<const uint8_t *>(text.data()), text.size()});
  if (executable)
    fs::permissions(path, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                    fs::perm_options::add);
}

// Stage of each job: 0 without dependencies, else one past its deepest dependency.
std::vector<int> stages(const std::vector<Job> &jobs) {
  std::vector<int> stage(jobs.size(), 0);
  for (size_t i = 0; i < jobs.size(); ++i)
    for (size_t d : jobs[i].deps)
      stage[i] = std::max(stage[i], stage[d] + 1);
  return stage;
}

BuildOptions buildOptions(const ordered_json &plan) {
  BuildOptions o;
  o.input = plan.at("input");
  o.output = plan.at("output");
  o.cache = plan.at("cache");
  o.report = plan.at("report");
  readBuildInputs(plan, o.files, o.scene);
  return o;
}

ordered_json readPlan(const std::string &path) {
  std::ifstream f(path);
  if (!f)
    throw Error(path + ": cannot open the Slurm plan");
  try {
    ordered_json plan = ordered_json::parse(f);
    if (plan.at("baker_version") != kBakerVersion)
      throw Error("written by baker " + plan.at("baker_version").get<std::string>() + ", this is " +
                  kBakerVersion);
    return plan;
  } catch (const Error &e) {
    throw Error(path + ": " + e.what());
  } catch (const std::exception &e) {
    throw Error(path + ": not a Slurm plan: " + e.what());
  }
}

} // namespace

void SlurmOptions::validate() const {
  if (folder.empty())
    throw Error("slurm folder: empty");
  if (maxArraySize < 0 || maxArraySize > 4000001) // Slurm's own bound
    throw Error("max array size: " + std::to_string(maxArraySize) + " is not in 0..4000001");
  if (jobsPerTask < 1 || jobsPerTask > 10000)
    throw Error("jobs per task: " + std::to_string(jobsPerTask) + " is not in 1..10000");
  if (cpusPerTask < 1 || cpusPerTask > 1024)
    throw Error("cpus per task: " + std::to_string(cpusPerTask) + " is not in 1..1024");
  if (crowdbake.empty() || !fs::path(crowdbake).is_absolute())
    throw Error("crowdbake executable: '" + crowdbake + "' is not an absolute path");
  for (char c : partition)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != ',')
      throw Error("partition: '" + partition + "' is not a partition name");
}

namespace {

// Per job of the plan: what a task needs to find it again (job_process.h).
ordered_json jobEntries(const BuildPlan &plan, const std::vector<int> &stage, int s) {
  ordered_json entries = ordered_json::array();
  for (size_t c = 0; c < plan.ranges.size(); ++c)
    for (size_t i = plan.ranges[c].first; i <= plan.ranges[c].second; ++i)
      if (stage[i] == s)
        entries.push_back({{"entry", plan.library.characters[c].entry},
                           {"job", i - plan.ranges[c].first},
                           {"key", plan.jobs[i].key}});
  return entries;
}

// A stage's tasks' --time and --mem: its jobs' largest limits (none where one job has none),
// the time for the jobs a task runs one after another, and a minute to plan them.
std::string taskLimits(const BuildOptions &o, const BuildPlan &plan, const std::vector<int> &stage,
                       int s, int jobsPerTask) {
  JobLimits most{-1, uint64_t(-1)};
  bool first = true;
  for (size_t c = 0; c < plan.ranges.size(); ++c)
    for (size_t i = plan.ranges[c].first; i <= plan.ranges[c].second; ++i) {
      if (stage[i] != s)
        continue;
      const JobLimits l = plan.library.characters[c].limits.over(o.jobLimits);
      const bool noTime = l.maxSeconds == 0 || (!first && most.maxSeconds == 0);
      const bool noMemory = l.maxMemoryMiB == 0 || (!first && most.maxMemoryMiB == 0);
      most.maxSeconds = noTime ? 0 : std::max(first ? 0 : most.maxSeconds, l.maxSeconds);
      most.maxMemoryMiB = noMemory ? 0 : std::max(first ? 0 : most.maxMemoryMiB, l.maxMemoryMiB);
      first = false;
    }
  std::string h;
  if (most.maxSeconds > 0)
    h += "#SBATCH --time=" +
         std::to_string(int64_t(std::ceil(most.maxSeconds * jobsPerTask / 60.0)) + 1) + "\n";
  if (most.maxMemoryMiB > 0)
    h += "#SBATCH --mem=" + std::to_string(most.maxMemoryMiB) + "M\n";
  return h;
}

} // namespace

int clusterMaxArraySize() {
  int size = 1001; // Slurm's default
  if (FILE *f = ::popen("scontrol show config 2>/dev/null", "r")) {
    char line[512];
    while (std::fgets(line, sizeof line, f))
      if (std::sscanf(line, " MaxArraySize = %d", &size) == 1)
        break;
    ::pclose(f);
  }
  return std::max(size, 1);
}

std::string writeSlurmScripts(const BuildOptions &build, const SlurmOptions &slurm) {
  slurm.validate();
  if (build.report.empty())
    throw Error("a Slurm build needs a report path: the collect job writes it");
  BuildOptions o = build;
  o.input = absolute(o.input);
  o.output = absolute(o.output);
  o.report = absolute(o.report);
  o.files.assetRoot = absolute(o.files.assetRoot);
  if (!o.scene.scene.empty())
    o.scene.scene = absolute(o.scene.scene);
  const BuildPlan plan = planBuild(o); // checks every manifest and hashes every input now
  const std::string folder = absolute(slurm.folder);
  std::error_code ec;
  fs::create_directories(fs::path(folder) / "logs", ec);
  if (ec)
    throw Error(folder + ": cannot create the Slurm folder: " + ec.message());

  const auto stage = stages(plan.jobs);
  const int stageCount = plan.jobs.empty() ? 0 : *std::max_element(stage.begin(), stage.end()) + 1;
  ordered_json p;
  p["baker_version"] = kBakerVersion;
  p["input"] = o.input;
  p["output"] = o.output;
  p["cache"] = absolute(plan.cache);
  p["report"] = o.report;
  writeBuildInputs(p, o.files, o.scene);
  p["jobs_per_task"] = slurm.jobsPerTask;
  p["cpus_per_task"] = slurm.cpusPerTask;
  p["stages"] = ordered_json::array();
  for (int s = 0; s < stageCount; ++s)
    p["stages"].push_back(jobEntries(plan, stage, s));
  const std::string planPath = folder + "/plan.json";
  writeText(planPath, p.dump(1) + "\n");

  auto header = [&](const std::string &name, const std::string &log) {
    std::string h = "#!/bin/bash\n#SBATCH --job-name=crowdbake-" + name + "\n";
    h += "#SBATCH --cpus-per-task=" + std::to_string(slurm.cpusPerTask) + "\n";
    h += "#SBATCH --output=" + folder + "/logs/" + log + "\n";
    if (!slurm.partition.empty())
      h += "#SBATCH --partition=" + slurm.partition + "\n";
    return h;
  };
  const std::string exe = quoted(slurm.crowdbake), planArg = quoted(planPath);
  const size_t arraySize =
      size_t(slurm.maxArraySize > 0 ? slurm.maxArraySize : clusterMaxArraySize());
  std::ostringstream summary, submit;
  submit << "#!/bin/bash\n# Submits the build's job arrays in order (afterok), then the collect "
            "job.\n# WAIT=1: wait for the collect job and exit with its status.\nset -euo "
            "pipefail\ncd \"$(dirname \"$0\")\"\nexec 2> >(tee logs/submit.log >&2)\ndep=()\n";
  for (int s = 0; s < stageCount; ++s) {
    const size_t n = p["stages"][s].size();
    const size_t tasks = (n + size_t(slurm.jobsPerTask) - 1) / size_t(slurm.jobsPerTask);
    // A stage of more tasks than the cluster's MaxArraySize is several arrays, each of task
    // ids 0..MaxArraySize-1 offset to the stage's.
    const size_t arrays = (tasks + arraySize - 1) / arraySize;
    const std::string limits = taskLimits(o, plan, stage, s, slurm.jobsPerTask);
    submit << "ids=()\n";
    for (size_t a = 0; a < arrays; ++a) {
      const size_t offset = a * arraySize, count = std::min(arraySize, tasks - offset);
      std::string name = "stage" + std::to_string(s);
      if (a > 0) // (appended in two steps: GCC 12 warns, falsely, of "." + to_string here)
        name.append(".").append(std::to_string(a));
      std::string script = header(name, name + "-%a.log") + limits;
      script += "#SBATCH --array=0-" + std::to_string(count - 1) + "\n";
      script += "exec " + exe + " build-task " + planArg + " " + std::to_string(s) + " $((" +
                std::to_string(offset) + " + SLURM_ARRAY_TASK_ID))\n";
      writeText(folder + "/" + name + ".sbatch", script);
      submit << "id=$(sbatch --parsable \"${dep[@]}\" " << name
             << ".sbatch)\nids+=(\"${id%%;*}\")\n"
             << "echo \"crowdbake: " << name << ": job array ${id%%;*} (" << count
             << (count == 1 ? " task)\" " : " tasks)\" ") << ">&2\n";
      summary << name << ".sbatch: "
              << (a + 1 < arrays ? count * size_t(slurm.jobsPerTask)
                                 : n - offset * size_t(slurm.jobsPerTask))
              << " jobs in " << count << (count == 1 ? " array task\n" : " array tasks\n");
    }
    submit << "dep=(--dependency=afterok:$(IFS=:; echo \"${ids[*]}\") --kill-on-invalid-dep=yes)\n";
  }
  std::string collect = header("collect", "collect.log");
  collect += "exec " + exe + " build-task " + planArg + " collect\n";
  writeText(folder + "/collect.sbatch", collect);
  submit << "if [ \"${WAIT:-0}\" = 1 ]; then\n"
            "  exec sbatch --parsable --wait \"${dep[@]}\" collect.sbatch\nfi\n"
            "sbatch --parsable \"${dep[@]}\" collect.sbatch\n";
  writeText(folder + "/submit.sh", submit.str(), true);
  summary << "collect.sbatch: writes the packs and the report " << o.report
          << "\nsubmit.sh: submits them in order (afterok)\n";
  return summary.str();
}

namespace {

// Runs submit.sh and waits for the collect job. The script's messages pass to stderr unless
// quiet; reading them to their end also waits for the script's tee into logs/submit.log, which
// may still be writing when the script has exited.
struct Submitted {
  int status = -1;
  std::string lastMessage;
};
Submitted submitAndWait(const fs::path &script, bool quiet) {
  const std::string command = "WAIT=1 '" + script.string() + "' 2>&1 >/dev/null";
  Submitted result;
  FILE *messages = popen(command.c_str(), "r");
  if (!messages)
    return result;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, messages)) {
    if (!quiet)
      std::fputs(buffer, stderr);
    std::string line(buffer);
    while (!line.empty() && (line.back() == '\n' || line.back() == '\r'))
      line.pop_back();
    if (!line.empty())
      result.lastMessage = line;
  }
  result.status = pclose(messages);
  return result;
}

} // namespace

ordered_json submitSlurmBuild(const BuildOptions &build, const SlurmOptions &slurm, bool quiet) {
  fs::remove(build.report);
  const fs::path folder = fs::absolute(slurm.folder);
  const Submitted run = submitAndWait(folder / "submit.sh", quiet);
  std::ifstream f(build.report);
  if (!f) {
    if (run.status == -1 || !WIFEXITED(run.status) || WEXITSTATUS(run.status) == 127)
      throw Error("cannot run sbatch (Debian: slurm-client): " + (folder / "submit.sh").string());
    const std::string &last = run.lastMessage;
    throw Error("the Slurm build wrote no report: " + (last.empty() ? "see" : last + "; see") +
                " " + (folder / "logs").string());
  }
  return ordered_json::parse(f);
}

void runSlurmTask(const std::string &planPath, int stage, int task) {
  const ordered_json p = readPlan(planPath);
  if (stage < 0 || size_t(stage) >= p["stages"].size())
    throw Error(planPath + ": no stage " + std::to_string(stage));
  const auto &entries = p["stages"][size_t(stage)];
  const size_t per = p.at("jobs_per_task"), first = size_t(std::max(task, 0)) * per;
  if (task < 0 || first >= entries.size())
    throw Error(planPath + ": stage " + std::to_string(stage) + " has no task " +
                std::to_string(task));
  const BuildOptions o = buildOptions(p);
  const ContentCache cache(o.cache);
  const CacheLease lease(o.cache);
  const size_t last = std::min(entries.size(), first + per);
  for (size_t k = first; k < last; ++k) {
    JobSpec spec;
    spec.library = o.input;
    spec.entry = entries[k].at("entry");
    spec.job = entries[k].at("job");
    spec.key = entries[k].at("key");
    spec.cache = o.cache;
    spec.threads = p.at("cpus_per_task");
    spec.files = o.files;
    spec.scene = o.scene;
    const std::vector<Job> jobs = planJobsOf(spec); // one character, not the whole library
    const Job &job = jobs[spec.job];
    std::string problem;
    if (cache.load(job.key, problem)) {
      std::printf("crowdbake: %s: cached\n", job.label().c_str());
      continue;
    }
    const auto t0 = std::chrono::steady_clock::now();
    std::string error;
    for (size_t d : job.deps)
      if (cache.recordedFailure(jobs[d].key) && !fs::exists(cache.entryPath(jobs[d].key))) {
        error = dependencyFailed(jobs[d]);
        break;
      }
    if (error.empty()) {
      try {
        bakeIntoCache(jobs, spec.job, cache, spec.threads);
      } catch (const std::bad_alloc &) {
        error = "out of memory";
      } catch (const std::exception &e) {
        error = e.what();
      }
    }
    for (char &c : error)
      c = c == '\n' ? ' ' : c;
    if (!error.empty())
      cache.recordFailure(job.key, error);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("crowdbake: %s: %s\n", job.label().c_str(),
                error.empty() ? (std::to_string(s).substr(0, 5) + " s").c_str()
                              : ("FAILED: " + error).c_str());
    std::fflush(stdout);
  }
}

BuildOptions slurmCollectOptions(const std::string &planPath) {
  const ordered_json p = readPlan(planPath);
  BuildOptions o = buildOptions(p);
  o.executor.workers = p.at("cpus_per_task");
  o.executor.progress = "none";
  o.executor.recordedFailures = true;
  return o;
}

} // namespace crowd
