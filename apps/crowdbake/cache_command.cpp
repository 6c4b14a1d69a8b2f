// crowdbake cache: what a build cache holds, and trimming it (cache_admin.h).
#include <cstdio>
#include <iostream>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "crowd/bake/cache_admin.h"

namespace crowd::cli {

namespace {

const char *const kCacheDescription =
    R"(Looks after a build's content cache (crowdbake build --cache DIR; a
library build's default is OUTDIR/.cache).

  stats DIR               entries, bytes, by job kind, and when entries were last used
  gc DIR --max-size SIZE  removes the least recently used entries until DIR holds at most SIZE
                          (500M, 20G, ...), never one used since the oldest running build
                          began; safe while builds read and write the same cache)";

const char *const kCacheExample = R"(
examples:
  crowdbake cache stats packs/.cache
  crowdbake cache gc /shared/crowdbake-cache --max-size 200G
)";

std::string megabytes(uint64_t bytes) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f MiB", double(bytes) / double(1 << 20));
  return b;
}

} // namespace

int cmdCache(int argc, char **argv) {
  CLI::App app(kCacheDescription, "crowdbake cache");
  app.footer(kCacheExample);
  app.require_subcommand(1);
  std::string folder, maxSize;
  bool json = false;
  auto *stats = app.add_subcommand("stats", "what the cache holds");
  stats->add_option("DIR", folder, "the cache folder")->required();
  stats->add_flag("--json", json, "the figures as JSON on stdout");
  auto *gc = app.add_subcommand("gc", "trim the cache to a size, least recently used first");
  gc->add_option("DIR", folder, "the cache folder")->required();
  gc->add_option("--max-size", maxSize, "the most the cache may hold: bytes, or 500M, 20G")
      ->required();
  gc->add_flag("--json", json, "the figures as JSON on stdout");
  if (!parseArgs(app, argc, argv))
    return 0;
  if (stats->parsed()) {
    const CacheStats s = cacheStats(folder);
    if (json) {
      std::cout << s.json().dump(1) << "\n";
      return 0;
    }
    std::printf("%s: %zu entries, %s\n", folder.c_str(), s.entries, megabytes(s.bytes).c_str());
    for (const auto &[kind, k] : s.kinds)
      std::printf("  %-10s %6zu entries  %s\n", kind.c_str(), k.entries,
                  megabytes(k.bytes).c_str());
    const auto j = s.json();
    std::printf("last used: %s .. %s; %zu recorded failures, %zu temporary files, %zu builds "
                "using it now\n",
                j["oldest_use"].get<std::string>().c_str(),
                j["newest_use"].get<std::string>().c_str(), s.failures, s.temporaries,
                s.liveBuilds);
    return 0;
  }
  uint64_t bytes = 0;
  try {
    bytes = parseSize(maxSize);
  } catch (const Error &e) {
    throw UsageError(std::string("--max-size: ") + e.what());
  }
  const GcResult r = collectGarbage(folder, bytes);
  if (json) {
    std::cout << r.json().dump(1) << "\n";
    return 0;
  }
  std::printf("%s: removed %zu entries (%s), kept %zu (%s)", folder.c_str(), r.removed,
              megabytes(r.removedBytes).c_str(), r.kept, megabytes(r.keptBytes).c_str());
  if (r.inUse)
    std::printf("; %zu kept over --max-size because a running build may use them", r.inUse);
  std::printf("\n");
  return 0;
}

} // namespace crowd::cli
