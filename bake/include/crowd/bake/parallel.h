// parallelFor: runs fn(i) for i in [0, n) on `threads` threads (0: all cores). Each index is
// independent and writes its own slot, so results never depend on scheduling.
#pragma once
#include <cstddef>
#include <functional>

namespace crowd {

int resolveThreads(int threads);
void parallelFor(size_t n, int threads, const std::function<void(size_t)> &fn);

} // namespace crowd
