// The build cache at scale: stats by kind, gc least recently used first down to a size, never
// an entry a live build may use, and sizes as users write them.
#include <filesystem>

#include <gtest/gtest.h>

#include "crowd/bake/cache_admin.h"
#include "crowd/bake/content_cache.h"
#include "crowd/formats/error.h"

using namespace crowd;
namespace fs = std::filesystem;

namespace {

struct Cache : ::testing::Test {
  // One folder a test: ctest runs the tests of one fixture side by side.
  const std::string folder =
      (fs::temp_directory_path() /
       ("crowd_cache_admin_" +
        std::string(::testing::UnitTest::GetInstance()->current_test_info()->name())))
          .string();
  ContentCache cache{folder};
  void SetUp() override { fs::remove_all(folder); }
  void TearDown() override { fs::remove_all(folder); }
  // An entry of about `bytes` last used `age` seconds ago.
  void add(const std::string &key, const std::string &kind, size_t bytes, int age) {
    Part p;
    p.chunks.push_back({0x41414141, 1, std::vector<uint8_t>(bytes, uint8_t(key[0]))});
    cache.store(key, p, kind);
    fs::last_write_time(cache.entryPath(key),
                        fs::file_time_type::clock::now() - std::chrono::seconds(age));
  }
  bool has(const std::string &key) { return fs::exists(cache.entryPath(key)); }
};

TEST_F(Cache, StatsCountEntriesByKind) {
  add("aa01", "mesh", 1000, 30);
  add("aa02", "mesh", 1000, 20);
  add("bb01", "link", 5000, 10);
  cache.recordFailure("cc01", "broken");
  const CacheStats s = cacheStats(folder);
  EXPECT_EQ(s.entries, 3u);
  EXPECT_EQ(s.kinds.at("mesh").entries, 2u);
  EXPECT_EQ(s.kinds.at("link").entries, 1u);
  EXPECT_GT(s.kinds.at("link").bytes, 5000u);
  EXPECT_EQ(s.failures, 1u);
  EXPECT_LT(s.oldestUse, s.newestUse - 15);
  EXPECT_THROW(cacheStats(folder + "/none"), Error);
}

TEST_F(Cache, GcRemovesTheLeastRecentlyUsedFirstDownToTheSize) {
  add("aa01", "mesh", 10000, 400); // oldest
  add("aa02", "mesh", 10000, 300);
  add("aa03", "link", 10000, 200);
  add("aa04", "link", 10000, 100); // newest
  const uint64_t total = cacheStats(folder).bytes;
  const GcResult r = collectGarbage(folder, total / 2);
  EXPECT_EQ(r.removed, 2u);
  EXPECT_FALSE(has("aa01"));
  EXPECT_FALSE(has("aa02"));
  EXPECT_TRUE(has("aa03"));
  EXPECT_TRUE(has("aa04"));
  EXPECT_LE(cacheStats(folder).bytes, total / 2);
  // Every file of an entry goes: no figures without a part.
  EXPECT_FALSE(fs::exists(cache.entryPath("aa01") + ".figs"));
  EXPECT_FALSE(cache.loadFigures("aa01"));
  EXPECT_TRUE(cache.loadFigures("aa03"));
}

TEST_F(Cache, GcKeepsWhatALiveBuildMayUse) {
  add("aa01", "mesh", 10000, 400);
  std::optional<CacheLease> build(folder); // a build that began now
  add("aa02", "mesh", 10000, 0);           // used by it
  GcResult r = collectGarbage(folder, 0);
  EXPECT_FALSE(has("aa01"));
  EXPECT_TRUE(has("aa02"));
  EXPECT_EQ(r.inUse, 1u);
  EXPECT_EQ(cacheStats(folder).liveBuilds, 1u);
  build.reset(); // the build ended
  r = collectGarbage(folder, 0);
  EXPECT_FALSE(has("aa02"));
  EXPECT_EQ(cacheStats(folder).liveBuilds, 0u);
}

TEST(CacheSize, SizesAsUsersWriteThem) {
  EXPECT_EQ(parseSize("1048576"), 1048576u);
  EXPECT_EQ(parseSize("500M"), 500ull << 20);
  EXPECT_EQ(parseSize("1.5G"), 3ull << 29);
  EXPECT_EQ(parseSize("2T"), 2ull << 40);
  for (const char *bad : {"", "M", "-1G", "10 G", "5X", "1e30T"})
    EXPECT_THROW(parseSize(bad), Error) << bad;
}

} // namespace
