#pragma once
// The nsmodal command line, a thin face: every subcommand's flags (CLI11)
// bound to its argument struct, and its command (commands.cc) that calls the
// libraries and writes files. main() parses and runs it; the fuzz target
// (fuzz/fuzz_cli.cc) parses it with arbitrary arguments.
#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "nsmodal/settings.h"

namespace nsmodal::cli {

struct OrbitsArgs {
  std::string scene, out, period;
  int impacts = 1;
  std::optional<std::string> sequence;  // the contact of each impact, "1,2"
  int threads = 0;
  std::optional<double> modes;  // analyse the first K linear modes only
  std::string format = "csv";   // the tables' format: csv or hdf5
};
struct OrbitArgs {
  std::string scene;
  int impacts = 1;
  std::optional<std::string> sequence;
  double period = 0.0;
  bool json = false;
};
struct ExploreArgs {
  std::string scene, period;
  int impacts = 3;
  int grid = 24;
  bool json = false;
  std::optional<std::string> follow;  // FROM:TO:STEP: follow each admissible new family (odd m) over that range
  std::optional<std::string> sequence;  // the contact of each impact ("1,2,1")
};

// `simulate` and `validate`: their settings' flags (made from the tables,
// simulate_settings.h and validate_settings.h) fill `flags`; a setting not
// given there falls back to the scene's table, then to its default.
struct SimulateArgs {
  std::string scene, out, format = "csv";
  SettingPatch flags;
};
struct ValidateArgs {
  std::string scene, out, format = "csv";
  SettingPatch flags;
};
struct SettingsArgs {
  bool json = false;
};
struct BenchArgs {
  std::string scene, out;
  bool quick = false;
};
// Flags of `figures`: the paper's Figs. 2-15 redrawn (commands.cc, report/figures.h).
struct FiguresArgs {
  std::string scene, out;
  std::optional<std::string> period;  // FROM:TO:STEP of the sweeps (default step:4 T_max:0.01)
  int threads = 0;
};
// Flags of `response` (commands.cc): one of frequency and amplitude is a
// grid FROM:TO:STEP, the other one value or a list a,b,c (default: the
// scene's [forcing]).
struct ResponseArgs {
  std::string scene, out;
  int impacts = 1, periods = 1;
  std::optional<std::string> frequency, amplitude;
  std::optional<std::string> sequence;  // the contact of each impact ("1,2")
  int validate = 0;  // periods simulated per orbit (0: no validation)
  std::vector<std::string> integrators{"exact"};
  int threads = 0;
};

// Flags of `continue` (commands.cc, issue 26): the response followed in one
// parameter of the scene over a range, the others held.
// With --second: the curves of a special point in the two parameters.
struct ContinueArgs {
  std::string scene, out, parameter, range;
  int impacts = 1, periods = 1;
  std::optional<std::string> sequence;
  std::optional<std::string> second, second_range, follow;
  std::optional<std::string> period;  // a free scene's period grid
};

int RunResponse(const ResponseArgs& a);
int RunContinue(const ContinueArgs& a);
int RunFigures(const FiguresArgs& a);
int RunOrbits(const OrbitsArgs& a);
int RunBench(const BenchArgs& a);
int RunValidate(const ValidateArgs& a);
int RunSimulate(const SimulateArgs& a);
int RunOrbit(const OrbitArgs& a);
int RunExplore(const ExploreArgs& a);
int RunSettings(const SettingsArgs& a);

struct CommandLine {
  CommandLine();
  CommandLine(const CommandLine&) = delete;
  CommandLine& operator=(const CommandLine&) = delete;

  // Runs the parsed subcommand; returns the exit status (README: 0 done,
  // 1 internal error, 2 bad input, 3 simulation stopped, 4 validation failed,
  // 5 a result could not be written), errors printed on stderr.
  int Run() const;

  CLI::App app{"nsmodal: nonsmooth modes of vibro-impact oscillators (Thorin, Legrand, Junca 2015)"};
  OrbitsArgs orbits;
  OrbitArgs orbit;
  ExploreArgs explore;
  SimulateArgs simulate;
  ValidateArgs validate;
  BenchArgs bench;
  ResponseArgs response;
  ContinueArgs cont;
  FiguresArgs figures;
  SettingsArgs settings;
  CLI::App *c_orbits = nullptr, *c_orbit = nullptr, *c_explore = nullptr, *c_sim = nullptr, *c_val = nullptr,
           *c_bench = nullptr, *c_fig = nullptr, *c_resp = nullptr, *c_cont = nullptr,
           *c_settings = nullptr;
};

// Parses argv and runs; CLI11's own errors exit 2 (0 for --help, --version).
int Main(int argc, char** argv);

}  // namespace nsmodal::cli
