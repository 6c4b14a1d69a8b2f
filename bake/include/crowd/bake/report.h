// Reporter: the one place warnings go. Printed on stderr as they happen (unless quiet) and
// gathered, with counts, for the --report JSON.
#pragma once
#include <string>
#include <vector>

namespace crowd {

class Reporter {
public:
  struct Warning {
    std::string code;    // short machine-readable key, e.g. "more_than_4_influences"
    std::string message; // one line for a human
    size_t count = 1;    // how many times it happened
  };
  void warn(std::string code, std::string message, size_t count = 1);
  const std::vector<Warning> &warnings() const { return warnings_; }
  bool quiet = false;

private:
  std::vector<Warning> warnings_;
};

} // namespace crowd
