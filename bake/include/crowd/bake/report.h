// Reporter: the one place warnings go. Printed on stderr as they happen (unless quiet) and
// gathered, with counts, for the --report JSON. Also where a long bake says what it is doing.
#pragma once
#include <functional>
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

  // Progress for a person watching: a line as each step of a long bake starts ("error budget:
  // clip 3 of 90 (Run)"), in order and one at a time (steps of clips baked side by side come
  // from the thread that takes the clip); nothing where no one listens.
  using Listener = std::function<void(const std::string &)>;
  Listener onStep;
  void step(const std::string &line) const {
    if (onStep)
      onStep(line);
  }

private:
  std::vector<Warning> warnings_;
};

} // namespace crowd
