#include "crowd/bake/slurm.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "crowd/bake/content_cache.h"
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
  o.files.assetRoot = plan.at("asset_root");
  o.files.maxFileBytes = plan.at("max_file_bytes");
  o.scene.scene = plan.at("scene");
  o.scene.screenHeight = plan.at("screen_height");
  o.scene.switchDistance = plan.at("switch_distance");
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
  p["asset_root"] = o.files.assetRoot;
  p["max_file_bytes"] = o.files.maxFileBytes;
  p["scene"] = o.scene.scene;
  p["screen_height"] = o.scene.screenHeight;
  p["switch_distance"] = o.scene.switchDistance;
  p["jobs_per_task"] = slurm.jobsPerTask;
  p["cpus_per_task"] = slurm.cpusPerTask;
  p["stages"] = ordered_json::array();
  for (int s = 0; s < stageCount; ++s) {
    ordered_json keys = ordered_json::array();
    for (size_t i = 0; i < plan.jobs.size(); ++i)
      if (stage[i] == s)
        keys.push_back(plan.jobs[i].key);
    p["stages"].push_back(keys);
  }
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
  std::ostringstream summary, submit;
  submit << "#!/bin/bash\n# Submits the build's job arrays in order (afterok), then the collect "
            "job.\n# WAIT=1: wait for the collect job and exit with its status.\nset -euo "
            "pipefail\ncd \"$(dirname \"$0\")\"\nexec 2> >(tee logs/submit.log >&2)\ndep=()\n";
  for (int s = 0; s < stageCount; ++s) {
    const size_t n = p["stages"][s].size();
    const size_t tasks = (n + size_t(slurm.jobsPerTask) - 1) / size_t(slurm.jobsPerTask);
    const std::string name = "stage" + std::to_string(s);
    std::string script = header(name, name + "-%a.log");
    script += "#SBATCH --array=0-" + std::to_string(tasks - 1) + "\n";
    script += "exec " + exe + " build-task " + planArg + " " + std::to_string(s) +
              " \"$SLURM_ARRAY_TASK_ID\"\n";
    writeText(folder + "/" + name + ".sbatch", script);
    submit << "id=$(sbatch --parsable \"${dep[@]}\" " << name << ".sbatch)\n"
           << "echo \"crowdbake: " << name << ": job array ${id%%;*} (" << tasks << " tasks)\" "
           << ">&2\ndep=(--dependency=afterok:${id%%;*} --kill-on-invalid-dep=yes)\n";
    summary << name << ".sbatch: " << n << " jobs in " << tasks << " array tasks\n";
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

void runSlurmTask(const std::string &planPath, int stage, int task) {
  const ordered_json p = readPlan(planPath);
  if (stage < 0 || size_t(stage) >= p["stages"].size())
    throw Error(planPath + ": no stage " + std::to_string(stage));
  const auto &keys = p["stages"][size_t(stage)];
  const size_t per = p.at("jobs_per_task"), first = size_t(std::max(task, 0)) * per;
  if (task < 0 || first >= keys.size())
    throw Error(planPath + ": stage " + std::to_string(stage) + " has no task " +
                std::to_string(task));
  const BuildPlan plan = planBuild(buildOptions(p));
  const auto stageOf = stages(plan.jobs);
  std::vector<size_t> mine; // this stage's jobs, in plan order
  for (size_t i = 0; i < plan.jobs.size(); ++i)
    if (stageOf[i] == stage)
      mine.push_back(i);
  if (mine.size() != keys.size())
    throw Error(p.at("input").get<std::string>() +
                ": the library changed since the Slurm scripts were written: write them again");
  const ContentCache cache(plan.cache);
  const int threads = p.at("cpus_per_task");
  const size_t last = std::min(keys.size(), first + per);
  for (size_t k = first; k < last; ++k) {
    const Job &job = plan.jobs[mine[k]];
    if (job.key != keys[k])
      throw Error(job.label() + ": its inputs changed since the Slurm scripts were written: "
                                "write them again");
    std::string problem;
    if (cache.load(job.key, problem)) {
      std::printf("crowdbake: %s: cached\n", job.label().c_str());
      continue;
    }
    const auto t0 = std::chrono::steady_clock::now();
    std::string error;
    std::vector<Part> deps;
    for (size_t d : job.deps) {
      if (auto part = cache.load(plan.jobs[d].key, problem)) {
        deps.push_back(std::move(*part));
        continue;
      }
      if (!cache.recordedFailure(plan.jobs[d].key))
        throw Error(job.label() + ": the part of " + plan.jobs[d].label() +
                    " is not in the cache " + plan.cache + (problem.empty() ? "" : ": " + problem));
      error = "not run: " + plan.jobs[d].label() + " failed";
      break;
    }
    if (error.empty()) {
      try {
        std::vector<const Part *> depParts;
        for (const auto &d : deps)
          depParts.push_back(&d);
        cache.store(job.key, runJob(job, depParts, {threads, {}}));
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
