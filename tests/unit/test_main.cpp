// The main of every gtest binary: runs the tests, then, where some were skipped and none failed,
// prints "SKIP: TEST: reason" for each and exits 77, which ctest (SKIP_RETURN_CODE) reports as
// skipped. gtest's own main exits 0 there: a skipped test would count as a pass.
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

int main(int argc, char **argv) {
  testing::InitGoogleTest(&argc, argv);
  const int failed = RUN_ALL_TESTS();
  const auto &unit = *testing::UnitTest::GetInstance();
  if (failed != 0 || unit.skipped_test_count() == 0)
    return failed;
  for (int s = 0; s < unit.total_test_suite_count(); ++s) {
    const auto &suite = *unit.GetTestSuite(s);
    for (int t = 0; t < suite.total_test_count(); ++t) {
      const auto &info = *suite.GetTestInfo(t);
      const auto &result = *info.result();
      if (!result.Skipped())
        continue;
      std::string why;
      for (int p = 0; p < result.total_part_count(); ++p)
        why += result.GetTestPartResult(p).message();
      std::printf("SKIP: %s.%s: %s\n", suite.name(), info.name(), why.c_str());
    }
  }
  return 77;
}
