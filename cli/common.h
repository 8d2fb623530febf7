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

// A progress callback for ParallelFor: a bar on stderr when it is a terminal,
// else a plain line every 10 s once the run has lasted that long.
std::function<void(long, long)> ProgressBar(const std::string& label);


}  // namespace nsmodal::cli
