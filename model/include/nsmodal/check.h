#pragma once
// Internal invariants, armed in every build (the first of the three tiers in
// error.h): a broken invariant is a bug in nsmodal, not a user's mistake, so
// it prints the condition with file and line and aborts. Debug-only checks
// stay `assert`.
#include <cstdio>
#include <cstdlib>

namespace nsmodal::internal {
[[noreturn]] inline void CheckFailed(const char* condition, const char* file, int line) {
  std::fprintf(stderr, "nsmodal: internal invariant violated: %s (%s:%d)\n", condition, file, line);
  std::abort();
}
}  // namespace nsmodal::internal

#define NSMODAL_CHECK(condition) \
  ((condition) ? static_cast<void>(0) : ::nsmodal::internal::CheckFailed(#condition, __FILE__, __LINE__))
