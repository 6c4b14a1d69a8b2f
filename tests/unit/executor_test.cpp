// The executor's use of the cache around jobs that run in child processes: the build holds only
// what it writes packs from.
#include <filesystem>

#include <gtest/gtest.h>

#include "crowd/bake/content_cache.h"
#include "crowd/bake/executor.h"
#include "crowd/formats/error.h"
#include "gltf_writer.h"

using namespace crowd;

namespace {

// A job run apart reads its dependencies in its own process: a cached dependency's figures
// come to the build, not its part; one not in the cache runs first; a pack's part is loaded.
TEST(Executor, JobsRunApartLeaveTheirCachedDependenciesUnloaded) {
  const std::string dir = test::tempDir("executor_apart");
  const ContentCache cache(dir);
  auto character = std::make_shared<CharacterManifest>();
  character->name = "c";
  std::vector<Job> jobs(3); // 0 (cached) and 1 (not) are read by 2, the link
  for (size_t i = 0; i < jobs.size(); ++i) {
    jobs[i].kind = i == 2 ? "link" : "mesh";
    jobs[i].character = character;
    jobs[i].key = std::string(64, char('a' + i));
  }
  jobs[2].deps = {0, 1};
  Part part;
  part.chunks.push_back({1, 1, {1, 2, 3}});
  part.figures["job"] = 0;
  cache.store(jobs[0].key, part, "mesh");

  std::vector<size_t> ranApart;
  ExecutorOptions options;
  options.workers = 1;
  options.progress = "none";
  options.runApart = [&](size_t i, int) {
    ranApart.push_back(i);
    Part p = part;
    p.figures["job"] = i;
    cache.store(jobs[i].key, p, jobs[i].kind);
    return JobProcessOutcome{true, false, false, ""};
  };
  const std::vector<JobOutcome> out = executeJobs(jobs, cache, options);
  EXPECT_EQ(ranApart, (std::vector<size_t>{1, 2}));
  EXPECT_TRUE(out[0].cached);
  EXPECT_TRUE(out[0].part.chunks.empty()) << "a cached dependency was loaded whole";
  EXPECT_EQ(out[0].part.figures["job"], 0);
  EXPECT_FALSE(out[1].cached);
  EXPECT_TRUE(out[1].part.chunks.empty());
  EXPECT_EQ(out[1].part.figures["job"], 1);
  ASSERT_EQ(out[2].part.chunks.size(), 1u) << "the pack's part was not loaded";
  EXPECT_EQ(out[2].part.chunks[0].payload, part.chunks[0].payload);
  std::filesystem::remove_all(dir);
}

// A job whose process cannot start fails alone, with the reason; its reader is not run. (It
// once ended the whole build in std::terminate: a build whose executable was being relinked.)
TEST(Executor, AJobWhoseProcessCannotStartFailsAlone) {
  const std::string dir = test::tempDir("executor_spawn");
  auto character = std::make_shared<CharacterManifest>();
  character->name = "c";
  std::vector<Job> jobs(3); // 0 cannot start; 1 reads it; 2 runs
  for (size_t i = 0; i < jobs.size(); ++i) {
    jobs[i].kind = "mesh";
    jobs[i].character = character;
    jobs[i].key = std::string(64, char('a' + i));
  }
  jobs[1].deps = {0};
  ExecutorOptions options;
  options.workers = 2;
  options.progress = "none";
  options.runApart = [&](size_t i, int) {
    if (i == 0)
      throw Error("cannot start /gone/crowdbake for a job: No such file or directory");
    ContentCache(dir).store(jobs[i].key, Part{}, jobs[i].kind);
    return JobProcessOutcome{true, false, false, ""};
  };
  const std::vector<JobOutcome> out = executeJobs(jobs, ContentCache(dir), options);
  EXPECT_TRUE(out[0].failed);
  EXPECT_EQ(out[0].error, "cannot start /gone/crowdbake for a job: No such file or directory");
  EXPECT_TRUE(out[1].failed);
  EXPECT_EQ(out[1].error, "not run: c: mesh failed");
  EXPECT_FALSE(out[2].failed);
  std::filesystem::remove_all(dir);
}

} // namespace
