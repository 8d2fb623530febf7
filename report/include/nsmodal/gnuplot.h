#pragma once
// Charts with gnuplot, started without a shell.
//
// DrawChart writes one script per format of report/style.toml,
// DIR/NAME.png.gp, NAME.svg.gp, NAME.pdf.gp and NAME.column.pdf.gp (the
// format's terminal, the style's chart set-up, then `body`) and runs
// `gnuplot SCRIPT` in DIR through
// posix_spawnp with an argument vector: no path, name or title ever passes
// through a shell. Scripts name their data files relative to DIR, so
// `gnuplot NAME.png.gp` run by hand from DIR redraws the chart. Each image is
// drawn under a temporary name and renamed when gnuplot succeeds and the
// image ends with its format's end marker (gnuplot exits 0 on a full disk,
// leaving a truncated image); gnuplot's messages go to DIR/NAME.EXT.gp.log,
// kept only when it fails and has said something. A stop request (stop.h)
// is polled before each chart and after each gnuplot run.
#include <string>

#include "nsmodal/output.h"

namespace nsmodal::report {

struct ChartStatus {
  bool drawn = false;
  std::string message;  // why not, when not drawn
};

// NAME: letters, digits, '_' and '-' only (an invariant of the callers).
// `aspect` > 0: the charts' height over width (else the formats', style.toml).
ChartStatus DrawChart(const OutputDir& dir, const std::string& name, const std::string& body, double aspect = 0.0);

}  // namespace nsmodal::report
