#include "fresh_process.h"

#include <cstdlib>
#include <fcntl.h>
#include <fstream>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

extern char **environ;

namespace crowd::test {

namespace {

constexpr const char *kOut = "CROWD_FRESH_PROCESS_OUT"; // set in the child: where its result goes

std::string readAll(const std::string &path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

} // namespace

bool inFreshProcess() { return std::getenv(kOut) != nullptr; }

std::optional<std::string> sameInAFreshProcess(const std::function<std::string()> &compute) {
  if (const char *out = std::getenv(kOut)) {
    std::ofstream(out, std::ios::binary) << compute();
    return std::nullopt;
  }
  const auto *info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string filter =
      std::string("--gtest_filter=") + info->test_suite_name() + "." + info->name();
  const std::string out = ::testing::TempDir() + "fresh_process_" + std::to_string(::getpid());
  std::vector<std::string> env = {std::string(kOut) + "=" + out, "MALLOC_PERTURB_=170"};
  for (char **e = environ; *e; ++e)
    if (std::string(*e).rfind("MALLOC_PERTURB_=", 0) != 0)
      env.push_back(*e);
  std::vector<char *> envp, argv;
  for (auto &e : env)
    envp.push_back(e.data());
  envp.push_back(nullptr);
  std::string self = "/proc/self/exe", quiet = "--gtest_brief=1";
  argv = {self.data(), const_cast<char *>(filter.c_str()), quiet.data(), nullptr};
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, "/proc/self/exe", &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  EXPECT_EQ(rc, 0) << "cannot start the fresh process";
  int status = 0;
  if (rc == 0)
    ::waitpid(pid, &status, 0);
  EXPECT_TRUE(rc == 0 && WIFEXITED(status) && WEXITSTATUS(status) == 0)
      << "the fresh process failed: status " << status;
  const std::string there = readAll(out), here = compute();
  std::remove(out.c_str());
  EXPECT_FALSE(there.empty()) << "the fresh process wrote no result";
  size_t at = 0;
  while (at < here.size() && at < there.size() && here[at] == there[at])
    ++at;
  EXPECT_TRUE(here == there) << "the results differ from byte " << at << " (" << here.size()
                             << " bytes here, " << there.size() << " in the fresh process)";
  return here;
}

} // namespace crowd::test
