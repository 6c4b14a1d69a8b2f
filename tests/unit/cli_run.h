// Test helper: runs a command line and checks the one-line error convention of our tools.
#pragma once
#include <string>

namespace crowd::test {

struct CliRun {
  int code;        // exit code, -1 when the process did not exit normally
  std::string err; // everything it wrote on stderr
};

// Runs `command` through the shell; stdout is discarded.
CliRun runCommand(const std::string &command);

// Exit code 1 and exactly one stderr line "TOOL: error: ..." that contains `needle`.
void expectOneLineError(const CliRun &r, const std::string &tool, const std::string &needle);

} // namespace crowd::test
