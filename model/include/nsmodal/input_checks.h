#pragma once
// Checks of user input that every front end applies the same way: the CLI
// (its flags), the Python module (its keywords) and the library's own entry
// points call these, so that a value refused by one is refused by all, with
// the name the user wrote (FieldNames, field_names.h).
#include <string>

#include "nsmodal/error.h"

namespace nsmodal {

// Worker threads: 0 (all cores) to kMaxThreads, the CLI's --threads range.
inline constexpr int kMaxThreads = 1024;

// Throws InputError(field) unless 0 <= threads <= kMaxThreads; returns it as
// an int. Takes a long long so that a Python int too large for an int is
// named, not wrapped.
inline int CheckThreads(long long threads, const std::string& field) {
  if (threads < 0 || threads > kMaxThreads) {
    throw InputError(field, "must lie in [0, " + std::to_string(kMaxThreads) + "] (0: all cores), got " +
                                std::to_string(threads));
  }
  return static_cast<int>(threads);
}

}  // namespace nsmodal
