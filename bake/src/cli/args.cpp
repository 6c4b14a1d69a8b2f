#include "args.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "crowd/formats/error.h"

namespace crowd::cli {

Args parse(int argc, char **argv, const std::set<std::string> &valued,
           const std::set<std::string> &flags) {
  Args a;
  for (int i = 2; i < argc; ++i) {
    std::string s = argv[i];
    if (s == "-o")
      s = "--output";
    if (s.rfind("--", 0) == 0) {
      std::string key = s.substr(2), value;
      bool inlineValue = false;
      if (auto eq = key.find('='); eq != std::string::npos) {
        value = key.substr(eq + 1);
        key = key.substr(0, eq);
        inlineValue = true;
      }
      if (valued.count(key)) {
        if (!inlineValue) {
          if (i + 1 >= argc)
            throw UsageError("option --" + key + " needs a value");
          value = argv[++i];
        }
        a.options[key] = value;
        a.lists[key].push_back(value);
      } else if (flags.count(key) && !inlineValue) {
        a.flags.insert(key);
      } else {
        throw UsageError("unknown option " + s);
      }
    } else {
      a.positional.push_back(s);
    }
  }
  return a;
}

double number(const Args &a, const std::string &key, double def) {
  if (!a.options.count(key))
    return def;
  const std::string &s = a.options.at(key);
  try {
    size_t used = 0;
    double v = std::stod(s, &used);
    if (used != s.size())
      throw std::invalid_argument(s);
    return v;
  } catch (const std::exception &) {
    throw UsageError("--" + key + " expects a number, got '" + s + "'");
  }
}

void oneInput(const Args &a, const char *command) {
  if (a.positional.size() != 1)
    throw UsageError(std::string(command) + " takes exactly one input (see crowdbake " + command +
                     " --help)");
}

bool progressWanted(const Args &a) { return !a.has("quiet") && isatty(2); }

uint32_t whole(const Args &a, const std::string &key, double def, double lo, double hi) {
  double v = number(a, key, def);
  if (v < lo || v > hi || v != std::floor(v))
    throw UsageError("--" + key + " must be an integer in [" + std::to_string(int64_t(lo)) + ", " +
                     std::to_string(int64_t(hi)) + "]");
  return uint32_t(v);
}

const std::set<std::string> kInputOptions = {"asset-root", "max-file-size", "max-memory",
                                             "max-seconds"};

const char *kInputHelp = R"(
untrusted input (every file a bake reads):
  --asset-root DIR     files a glTF names (buffers, images) must resolve inside DIR (default:
                       the glTF's own folder); '..' leaving it, absolute paths, links out of
                       it and non-regular files (devices, FIFOs, folders) are errors
  --max-file-size MIB  largest input file read (default 1024 MiB), checked before reading
  --max-memory MIB     stop with an error past this resident memory (default: 3/4 of RAM)
  --max-seconds S      stop with an error after S seconds (default 3600); either limit
                       writes nothing
)";

crowd::InputPolicy inputPolicy(const Args &a) {
  crowd::InputPolicy p;
  p.assetRoot = a.get("asset-root");
  if (a.options.count("max-file-size"))
    p.maxFileBytes = uint64_t(whole(a, "max-file-size", 1024, 1, 1 << 22)) << 20;
  try {
    p.validate();
  } catch (const crowd::Error &e) {
    throw UsageError(e.what());
  }
  return p;
}

crowd::ResourceLimits resourceLimits(const Args &a) {
  crowd::ResourceLimits r;
  r.maxMemoryMiB = uint64_t(number(a, "max-memory", 0));
  r.maxSeconds = number(a, "max-seconds", r.maxSeconds);
  try {
    r.validate();
  } catch (const crowd::Error &e) {
    throw UsageError(e.what());
  }
  return r;
}

void writeJson(const std::string &path, const nlohmann::ordered_json &j) {
  std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp);
    f << j.dump(2) << "\n";
    if (!f)
      throw crowd::Error(path + ": cannot write report");
  }
  std::filesystem::rename(tmp, path);
}

nlohmann::ordered_json warningsJson(const Reporter &reporter) {
  auto list = nlohmann::ordered_json::array();
  for (const auto &w : reporter.warnings())
    list.push_back({{"code", w.code}, {"message", w.message}, {"count", w.count}});
  return list;
}

} // namespace crowd::cli
