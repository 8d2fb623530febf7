#pragma once
// Thin command layer of the nsmodal CLI: parse, call the libraries, write files.
#include <string>
#include <vector>

namespace nsmodal::cli {

struct PeriodRange {
  double from, to, step;
  std::vector<double> Values() const;
};
// "FROM:TO:STEP"; throws InputError naming --period.
PeriodRange ParsePeriodRange(const std::string& text);

struct OrbitsArgs {
  std::string scene, out, period;
  int impacts = 1;
  int threads = 0;
  double t2_step = 0.01;
};
struct OrbitArgs {
  std::string scene;
  int impacts = 1;
  double period = 0.0;
  bool json = false;
  double t2_step = 0.01;
};
struct ExploreArgs {
  std::string scene, period;
  int impacts = 3;
  int grid = 24;
  bool json = false;
};

int RunOrbits(const OrbitsArgs& a);
int RunOrbit(const OrbitArgs& a);
int RunExplore(const ExploreArgs& a);

}  // namespace nsmodal::cli
