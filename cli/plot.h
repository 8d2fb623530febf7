#pragma once
// Charts with gnuplot: DIR/NAME.gp is written and run twice, for NAME.png
// (pngcairo) and NAME.svg. The data files stay beside it.
#include <string>

namespace nsmodal::cli {

// body: gnuplot commands after the terminal and output are set. Returns false
// and says why on stderr when gnuplot is missing or fails.
bool Plot(const std::string& dir, const std::string& name, const std::string& body);

}  // namespace nsmodal::cli
