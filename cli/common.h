#pragma once
// Helpers shared by the commands (commands.cc, figures.cc).
#include <functional>
#include <optional>
#include <string>

#include "nsmodal/modal_basis.h"
#include "nsmodal/orbit.h"
#include "nsmodal/scene.h"
#include "nsmodal/stability.h"

namespace nsmodal::cli {

// A progress callback for ParallelFor drawing a bar on stderr, or none when
// stderr is not a terminal.
std::function<void(long, long)> ProgressBar(const std::string& label);

// Floquet multipliers of a potential orbit; none for an orbit that is not.
std::optional<Stability> StabilityOf(const AnalysisBasis& b, const Orbit& o);

}  // namespace nsmodal::cli
