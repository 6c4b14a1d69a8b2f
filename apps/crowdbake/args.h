// Command-line pieces shared by crowdbake's sub-commands (CLI11): parsing with --help, the
// options every bake takes (one input, -o, --report, --quiet and the untrusted-input limits),
// option structs checked by their own validate(), and the JSON report writer.
#pragma once
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "crowd/bake/anim_bake.h"
#include "crowd/bake/input_files.h"
#include "crowd/bake/manifest.h"
#include "crowd/bake/report.h"
#include "crowd/bake/resource_guard.h"
#include "crowd/formats/error.h"

namespace crowd::cli {

// Bad usage: exit code 2 with the message.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// One line on stderr: "crowdbake: usage: ..." for a UsageError, "crowdbake: error: ..." for any
// other (newlines in the message become spaces). The caller picks the exit code.
void printFailure(const std::exception &e);

// Parses argv[2..] into `app`. False when --help was asked for (printed on stdout); a parse
// error throws UsageError.
bool parseArgs(CLI::App &app, int argc, char **argv);

// "example: ..." under a command's options.
void example(CLI::App &app, const std::string &text);

// An option struct's validate(), its error as a usage error (the field named).
template <class Options> void validated(const Options &options) {
  try {
    options.validate();
  } catch (const Error &e) {
    throw UsageError(e.what());
  }
}

// --asset-root, --max-file-size, --max-memory, --max-seconds: where and how much a command that
// reads untrusted input may read, and the resource guard's limits.
struct InputArgs {
  InputPolicy policy;
  ResourceLimits limits;
  void add(CLI::App &app);
  void finish(); // after parsing: validates both (usage errors)

private:
  double maxFileMiB_ = double(policy.maxFileBytes >> 20);
};

// What every bake command takes besides its own options.
struct BakeArgs {
  std::string input, output, report;
  bool quiet = false;
  InputArgs files;
  void add(CLI::App &app, const char *inputHelp = "the glTF character (.glb or .gltf)");
  bool progress() const; // stderr is a terminal and --quiet is not given
  // After parsing: the one-character manifest of the input (name: its stem; bake settings are
  // the command's to fill), and runs `kind`'s job of it under the resource guard.
  CharacterManifest manifest() const;
  void runJob(const CharacterManifest &m, const std::string &command, const std::string &kind,
              int threads) const;
};

// An --outfit argument, [NAME=]FILE: its name defaults to the file name without extension and
// without an "outfit_" prefix.
std::pair<std::string, std::string> outfitNameAndFile(const std::string &arg);

// --error-budget, --fps, --precision and --max-width of the animation bake (anim, lod, outfits).
void addAnimOptions(CLI::App &app, AnimBakeOptions &anim);
// --threads of any bake.
void addThreads(CLI::App &app, int &threads);

// What --mesh bakes when it is not given (ImportOptions::mesh).
extern const char *const kEveryMesh;

void writeJson(const std::string &path, const nlohmann::ordered_json &j); // atomically

} // namespace crowd::cli
