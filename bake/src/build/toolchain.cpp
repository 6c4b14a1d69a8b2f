#include <string>

#include <gnu/libc-version.h>

#include "crowd/bake/provenance.h"

namespace crowd {

std::string toolchain() {
#if defined(__clang__)
  std::string compiler = std::string("clang ") + __clang_version__;
#elif defined(__GNUC__)
  std::string compiler = std::string("gcc ") + __VERSION__;
#else
  std::string compiler = "an unknown compiler";
#endif
#if defined(__x86_64__)
  const char *arch = "x86_64";
#elif defined(__aarch64__)
  const char *arch = "aarch64";
#else
  const char *arch = "another architecture";
#endif
  return compiler + ", glibc " + gnu_get_libc_version() + ", " + arch;
}

} // namespace crowd
