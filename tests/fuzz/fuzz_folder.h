// The private folder a fuzz target writes its inputs to (the readers it fuzzes read files, as
// the bakes do): made once per process under $TMPDIR (else /tmp), named after the target.
#pragma once

#include <cstdlib>
#include <string>

namespace crowd::fuzz {

// A new folder $TMPDIR/crowd_NAME_fuzz_XXXXXX; aborts where it cannot be made (the fuzzer
// cannot run without it).
inline std::string makeFolder(const char *name) {
  const char *tmp = std::getenv("TMPDIR");
  std::string pattern = std::string(tmp ? tmp : "/tmp") + "/crowd_" + name + "_fuzz_XXXXXX";
  if (!mkdtemp(pattern.data()))
    std::abort();
  return pattern;
}

} // namespace crowd::fuzz
