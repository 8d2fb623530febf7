#include <gtest/gtest.h>

#include <stdexcept>

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

}  // namespace
}  // namespace nsmodal
