#include "crowd/bake/malloc_tuning.h"

#include <cstdlib> // defines __GLIBC__ where the C library is glibc
#include <string>

#ifdef __GLIBC__
#include <malloc.h>
#include <unistd.h>
#endif

namespace crowd {

void keepFreedMemory() {
#ifdef __GLIBC__
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
}

void useHugePages(char *const argv[]) {
#ifdef __GLIBC__
  const char *now = std::getenv("GLIBC_TUNABLES");
  const std::string tunables = now ? now : "";
  if (tunables.find("glibc.malloc.hugetlb") != std::string::npos)
    return; // by the user, or by this function before it ran the program again
  const std::string with = (tunables.empty() ? "" : tunables + ":") + "glibc.malloc.hugetlb=1";
  if (setenv("GLIBC_TUNABLES", with.c_str(), 1) == 0)
    execv("/proc/self/exe", argv);
#else
  (void)argv;
#endif
}

} // namespace crowd
