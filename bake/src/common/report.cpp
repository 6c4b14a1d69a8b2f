#include "crowd/bake/report.h"

#include <cstdio>

namespace crowd {

void Reporter::warn(std::string code, std::string message, size_t count) {
  if (!quiet)
    std::fprintf(stderr, "crowdbake: warning: %s\n", message.c_str());
  warnings_.push_back({std::move(code), std::move(message), count});
}

} // namespace crowd
