#pragma once
// Helpers shared by the commands (commands.cc, figures.cc).
#include <functional>
#include <optional>
#include <string>

#include "nsmodal/field_names.h"
#include "nsmodal/modal_basis.h"
#include "nsmodal/orbit.h"
#include "nsmodal/scene.h"
#include "nsmodal/stability.h"

namespace nsmodal::cli {

// One settings path: a value from its flag if given, else from the scene's
// table if there, else the default; `names` records where it came from, so
// that validation names the flag or the key the user wrote (the default
// keeps the table's key as its name).
template <class T>
T Pick(const std::optional<T>& flag, const std::string& flag_name, const std::optional<T>& key,
       const std::string& key_name, T fallback, const std::string& member, FieldNames& names) {
  if (flag) {
    names.Set(member, flag_name);
    return *flag;
  }
  if (key) {
    names.Set(member, key_name);
    return *key;
  }
  return fallback;
}

// A progress callback for ParallelFor: a bar on stderr when it is a terminal,
// else a plain line every 10 s once the run has lasted that long.
std::function<void(long, long)> ProgressBar(const std::string& label);


}  // namespace nsmodal::cli
