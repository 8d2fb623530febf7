#include "plot.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>

namespace nsmodal::cli {

bool Plot(const std::string& dir, const std::string& name, const std::string& body) {
  const std::filesystem::path base = std::filesystem::path(dir) / name;
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) {
    std::cerr << "warning: gnuplot not found: " << name << " not drawn (apt-get install gnuplot-nox)\n";
    return false;
  }
  bool ok = true;
  for (const auto& [ext, terminal] : {std::pair<std::string, std::string>{"png", "pngcairo size 900,650 font ',11'"},
                                      {"svg", "svg size 900,650 dynamic font ',11'"}}) {
    const std::string script = base.string() + "." + ext + ".gp";
    std::ofstream(script) << "set terminal " << terminal << "\nset output '" << base.string() << "." << ext << "'\n"
                          << "cd '" << dir << "'\n"
                          << body << "\n";
    const std::string cmd = "gnuplot '" + script + "' 2>'" + script + ".log'";
    if (std::system(cmd.c_str()) != 0) {
      std::cerr << "warning: gnuplot failed on " << script << " (see " << script << ".log)\n";
      ok = false;
    } else {
      std::filesystem::remove(script + ".log");
    }
  }
  return ok;
}

}  // namespace nsmodal::cli
