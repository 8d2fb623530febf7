#include "plot.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>

namespace nsmodal::cli {

bool Plot(const std::string& dir, const std::string& name, const std::string& body) {
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) {
    std::cerr << "warning: gnuplot not found: " << name << " not drawn (apt-get install gnuplot-nox)\n";
    return false;
  }
  bool ok = true;
  for (const auto& [ext, terminal] : {std::pair<std::string, std::string>{"png", "pngcairo size 900,650 font ',11'"},
                                      {"svg", "svg size 900,650 dynamic font ',11'"}}) {
    // The script sits beside its data and names files relative to it, so it
    // can be rerun by hand from DIR: gnuplot NAME.png.gp
    const std::string script = name + "." + ext + ".gp";
    std::ofstream(std::filesystem::path(dir) / script)
        << "set terminal " << terminal << "\nset output '" << name << "." << ext << "'\n"
        << body << "\n";
    const std::string cmd = "cd '" + dir + "' && gnuplot '" + script + "' 2>'" + script + ".log'";
    if (std::system(cmd.c_str()) != 0) {
      std::cerr << "warning: gnuplot failed on " << dir << "/" << script << " (see its .log)\n";
      ok = false;
    } else {
      std::filesystem::remove(std::filesystem::path(dir) / (script + ".log"));
    }
  }
  return ok;
}

}  // namespace nsmodal::cli
