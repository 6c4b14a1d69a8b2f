// A library build's job processes, the parts that need no child: the spec a child reads, the
// one entry it loads of a library, and limits that change no job key.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "crowd/bake/content_cache.h"
#include "crowd/bake/job_process.h"
#include "crowd/formats/error.h"

using namespace crowd;

namespace {

const std::string kBody = std::string(CROWD_SOURCE_DIR) + "/tests/data/blender/trooper_cm.glb";
InputPolicy sourceTree() { // absolute paths inside the source tree
  InputPolicy p;
  p.assetRoot = CROWD_SOURCE_DIR;
  return p;
}

TEST(JobProcess, TheSpecComesBackAsWritten) {
  JobSpec s;
  s.library = "lib.json";
  s.entry = 7;
  s.job = 2;
  s.key = "ab12";
  s.cache = "/c";
  s.threads = 3;
  s.files.assetRoot = "/assets";
  s.files.maxFileBytes = 1234;
  s.scene.scene = "market.json";
  s.scene.screenHeight = 720;
  s.scene.switchDistance = 25;
  s.limits = {8.5, 512};
  const JobSpec t = JobSpec::parse(s.text());
  EXPECT_EQ(t.text(), s.text());
  EXPECT_EQ(t.entry, 7u);
  EXPECT_EQ(t.limits.maxMemoryMiB, 512u);
  EXPECT_THROW(JobSpec::parse("{\"library\": 1}"), Error);
  EXPECT_THROW(JobSpec::parse("not json"), Error);
  s.limits.maxSeconds = -1;
  EXPECT_THROW(JobSpec::parse(s.text()), Error); // the limits are checked
}

TEST(JobProcess, AManifestsLimitsOverTheBuildsAndInNoKey) {
  EXPECT_EQ(JobLimits({0, 300}).over({8, 100}).maxSeconds, 8);
  EXPECT_EQ(JobLimits({0, 300}).over({8, 100}).maxMemoryMiB, 300u);
  const std::string plain = R"({"name": "a", "body": ")" + kBody + R"("})";
  const std::string bounded =
      R"({"name": "a", "body": ")" + kBody + R"(", "limits": {"seconds": 5, "memory_mib": 64}})";
  const CharacterManifest p = parseManifest(plain, "a.json", sourceTree()),
                          b = parseManifest(bounded, "a.json", sourceTree());
  EXPECT_EQ(b.limits.maxSeconds, 5);
  EXPECT_EQ(b.limits.maxMemoryMiB, 64u);
  auto keys = [](const CharacterManifest &m) {
    auto jobs = planCharacter(std::make_shared<CharacterManifest>(m), 0);
    keyJobs(jobs);
    std::vector<std::string> k;
    for (const auto &j : jobs)
      k.push_back(j.key);
    return k;
  };
  EXPECT_EQ(keys(p), keys(b)); // a limit changes no byte, so no key
  try {
    parseManifest(R"({"name": "a", "body": ")" + kBody + R"(", "limits": {"minutes": 5}})",
                  "a.json", sourceTree());
    FAIL() << "an unknown limit was taken";
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("/limits/minutes: unknown key"), std::string::npos)
        << e.what();
  }
}

TEST(JobProcess, AChildLoadsOnlyItsEntryOfTheLibrary) {
  const auto folder = std::filesystem::temp_directory_path() / "crowd_job_process_test";
  std::filesystem::create_directories(folder);
  const std::string path = (folder / "lib.json").string();
  std::ofstream(path) << R"({"characters": [{"name": "gone", "body": "missing.glb"},
                                            {"name": "b", "body": ")"
                      << kBody << R"("}]})";
  EXPECT_THROW(loadLibrary(path, sourceTree()),
               Error); // the whole library: entry 0's body is missing
  const Library one = loadLibrary(path, sourceTree(), 1);
  ASSERT_EQ(one.characters.size(), 1u);
  EXPECT_EQ(one.characters[0].name, "b");
  EXPECT_EQ(one.characters[0].entry, 1u);
  EXPECT_THROW(loadLibrary(path, sourceTree(), 2), Error);
  std::filesystem::remove_all(folder);
}

TEST(JobProcess, AChildBakesAgainADependencyTheCacheLost) {
  // As after a gc between the build's look at the cache and the child's read: the link's mesh
  // part is not there, so the child bakes it again and stores both.
  const auto folder = std::filesystem::temp_directory_path() / "crowd_job_child_test";
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  const std::string path = (folder / "a.json").string();
  std::ofstream(path) << R"({"name": "a", "body": ")" << kBody << R"(", "lod": false})";
  auto jobs = planCharacter(
      std::make_shared<CharacterManifest>(loadLibrary(path, sourceTree()).characters[0]), 0);
  keyJobs(jobs);
  ASSERT_EQ(jobs.back().kind, "link");
  JobSpec spec;
  spec.library = path;
  spec.job = jobs.size() - 1;
  spec.key = jobs.back().key;
  spec.cache = (folder / "cache").string();
  spec.files = sourceTree();
  runJobSpec(spec);
  const ContentCache cache(spec.cache);
  for (const auto &j : jobs)
    EXPECT_TRUE(std::filesystem::exists(cache.entryPath(j.key))) << j.label();
  spec.key = "00ff"; // not the key the character plans to now: its inputs changed
  EXPECT_THROW(runJobSpec(spec), Error);
  std::filesystem::remove_all(folder);
}

} // namespace
