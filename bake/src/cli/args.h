// Command-line parsing shared by crowdbake's sub-commands: options with values (repeatable ones
// gather every value), flags, positional inputs, numbers, and the JSON report writer.
#pragma once
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "crowd/bake/input_files.h"
#include "crowd/bake/report.h"
#include "crowd/bake/resource_guard.h"

namespace crowd::cli {

// Bad usage: exit code 2 with the message.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Args {
  std::vector<std::string> positional;
  std::map<std::string, std::string> options; // the last value of each
  std::map<std::string, std::vector<std::string>> lists; // every value, in order
  std::set<std::string> flags;
  bool has(const std::string &k) const { return options.count(k) || flags.count(k); }
  std::string get(const std::string &k, const std::string &def = "") const {
    auto it = options.find(k);
    return it == options.end() ? def : it->second;
  }
};

// argv[2..]: `valued` options take a value (--key VALUE or --key=VALUE), `flags` none; -o is
// --output.
Args parse(int argc, char **argv, const std::set<std::string> &valued,
           const std::set<std::string> &flags);
double number(const Args &a, const std::string &key, double def);
// An integer option in [lo, hi].
uint32_t whole(const Args &a, const std::string &key, double def, double lo, double hi);
void oneInput(const Args &a, const char *command);
bool progressWanted(const Args &a); // stderr is a terminal and --quiet is not given
void writeJson(const std::string &path, const nlohmann::ordered_json &j); // atomically
// Options of every command that reads untrusted input: --asset-root DIR, --max-file-size MIB,
// --max-memory MIB, --max-seconds S; their help text, and the structs they fill.
extern const std::set<std::string> kInputOptions;
extern const char *kInputHelp;
crowd::InputPolicy inputPolicy(const Args &a);
crowd::ResourceLimits resourceLimits(const Args &a);

// The reporter's warnings for a --report file: [{code, message, count}, ...].
nlohmann::ordered_json warningsJson(const Reporter &reporter);

} // namespace crowd::cli
