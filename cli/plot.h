#pragma once
// Charts with gnuplot: DIR/NAME.png.gp and DIR/NAME.svg.gp are written and run
// from DIR (pngcairo and svg terminals); the data files stay beside them.
#include <string>

namespace nsmodal::cli {

// body: gnuplot commands after the terminal and output are set. Returns false
// and says why on stderr when gnuplot is missing or fails.
bool Plot(const std::string& dir, const std::string& name, const std::string& body);

}  // namespace nsmodal::cli
