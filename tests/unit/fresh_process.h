// Test helper: a result computed here and again in a fresh process of this test binary, for
// determinism across processes (another address layout, fresh memory filled with other bytes),
// which two runs in one process cannot show.
#pragma once
#include <functional>
#include <optional>
#include <string>

namespace crowd::test {

// In the test that calls it: runs `compute` here and in a child process that runs the same test
// alone with MALLOC_PERTURB_ set; fails the test (naming the first differing byte) where the two
// results differ. In that child it writes its result for the parent and returns nothing: the
// test then returns. In the parent it returns the result computed here, for further checks.
std::optional<std::string> sameInAFreshProcess(const std::function<std::string()> &compute);

// True in that child process.
bool inFreshProcess();

// `values` as bytes, for a result of floats.
template <typename T> std::string bytesOf(const T &values) {
  return {reinterpret_cast<const char *>(values.data()), values.size() * sizeof(values[0])};
}

} // namespace crowd::test
