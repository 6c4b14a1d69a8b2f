#include "cli_run.h"

#include <array>
#include <cstdio>
#include <sys/wait.h>

#include <gtest/gtest.h>

namespace crowd::test {

CliRun runCommand(const std::string &command) {
  std::string cmd = command + " 2>&1 >/dev/null";
  FILE *p = popen(cmd.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf;
  while (size_t n = fread(buf.data(), 1, buf.size(), p))
    out.append(buf.data(), n);
  int status = pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

void expectOneLineError(const CliRun &r, const std::string &tool, const std::string &needle) {
  EXPECT_EQ(r.code, 1) << r.err;
  ASSERT_FALSE(r.err.empty());
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "more than one line: " << r.err;
  EXPECT_EQ(r.err.rfind(tool + ": error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(needle), std::string::npos) << "expected '" << needle << "' in: " << r.err;
}

} // namespace crowd::test
