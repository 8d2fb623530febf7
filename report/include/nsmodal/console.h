#pragma once
// The text a person reads on the console: the lines and tables the commands
// print besides their files. Each function writes to `out` (the CLI passes
// std::cout) and leaves its format flags as it found them.
#include <ostream>

#include "nsmodal/truncation.h"

namespace nsmodal::report {

// "modal truncation: k of N modes kept (up to w_k rad/s; the first neglected
// w_k+1 rad/s); residual flexibility f m/N", no end of line: each command
// goes on with what the bound means for it.
void PrintTruncation(std::ostream& out, const ModalTruncation& t);

// The line of a sweep on the kept modes (orbits --modes): PrintTruncation
// and the bound's column in orbits.csv.
void PrintSweepTruncation(std::ostream& out, const ModalTruncation& t);

}  // namespace nsmodal::report
