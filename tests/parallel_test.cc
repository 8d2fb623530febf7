#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>

#include "nsmodal/parallel.h"

namespace nsmodal {
namespace {

TEST(ParallelFor, VisitsEveryIndexOnce) {
  std::vector<int> hits(1000, 0);
  ParallelFor(1000, 2, [&](long i) { ++hits[i]; });
  for (int h : hits) EXPECT_EQ(h, 1);
}

TEST(ParallelFor, RethrowsTheFirstExceptionOnTheCaller) {
  // A worker's exception must reach the caller, not std::terminate.
  EXPECT_THROW(ParallelFor(100, 2, [](long i) {
                 if (i == 37) throw std::runtime_error("boom");
               }),
               std::runtime_error);
}

// A progress callback that throws while the pool works (a Python callable
// that raised) reaches the caller too: before, the pool's running threads
// were destroyed by the unwinding and the process terminated.
TEST(ParallelFor, AProgressCallbackThatThrowsReachesTheCaller) {
  std::atomic<long> visited{0};
  EXPECT_THROW(ParallelFor(
                   50, 2,
                   [&](long) {
                     std::this_thread::sleep_for(std::chrono::milliseconds(10));
                     ++visited;
                   },
                   [](long, long) { throw std::runtime_error("progress"); }),
               std::runtime_error);
  EXPECT_LT(visited.load(), 50);  // the work stopped early
}

}  // namespace
}  // namespace nsmodal
