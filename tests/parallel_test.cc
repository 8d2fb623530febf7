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

// With a progress callback the calling thread works too: every item runs on
// one of `threads` threads, the caller among them. (It used to only report,
// leaving one core of two idle in every CLI sweep: the 100-mass 1-ipp sweep
// took 3.8 s instead of 2.0.) Items sleep so that both threads get some.
TEST(ParallelFor, TheCallerWorksWhileItReportsProgress) {
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<long> by_caller{0};
  long reports = 0;
  ParallelFor(
      40, 2,
      [&](long) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        if (std::this_thread::get_id() == caller) ++by_caller;
      },
      [&](long, long) { ++reports; });
  EXPECT_GT(by_caller.load(), 0);
  EXPECT_GE(reports, 2);  // the start and the end at least
}

}  // namespace
}  // namespace nsmodal
