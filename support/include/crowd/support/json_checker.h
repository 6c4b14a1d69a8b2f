// JSON input files a user writes (scenes, character manifests, libraries): parsing and checks
// whose errors say "FILE:LINE:COLUMN: /key/path: what". nlohmann::json keeps no source
// positions, so a semantic error points at the first occurrence of the offending key after its
// parent's key, which is where a reader would look.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "crowd/formats/limits.h"

namespace crowd::support {

class JsonChecker {
public:
  using Keys = std::vector<std::string>;
  JsonChecker(const std::string &text, const std::string &path) : text_(text), path_(path) {}

  // Parses the text; a syntax error names its line and column.
  nlohmann::json parse() const;
  [[noreturn]] void fail(const Keys &keys, const std::string &what) const;
  void onlyKeys(const nlohmann::json &j, const Keys &keys, const Keys &allowed) const;
  double number(const nlohmann::json &j, const Keys &keys, double lo, double hi) const;
  std::string string(const nlohmann::json &j, const Keys &keys) const; // non-empty
  bool boolean(const nlohmann::json &j, const Keys &keys) const;
  const std::string &path() const { return path_; }

private:
  const std::string &text_;
  const std::string &path_;
};

// Throws naming `path`, line and column where JSON text nests deeper than `limit` arrays and
// objects. Run before any parser sees untrusted JSON: parsers and the trees they build recurse.
void checkJsonDepth(std::string_view text, const std::string &path, int limit = limits::kJsonDepth);

// Line and column (1-based) of byte `offset` in `text`, as "LINE:COLUMN".
std::string lineColumn(const std::string &text, size_t offset);

} // namespace crowd::support
