#pragma once
// The nsmodal command line: every subcommand's flags (CLI11) bound to its
// argument struct, and the dispatch to the command. main() parses and runs
// it; the fuzz target (fuzz/fuzz_cli.cc) parses it with arbitrary arguments.
#include <CLI/CLI.hpp>

#include "commands.h"

namespace nsmodal::cli {

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
  FiguresArgs figures;
  SettingsArgs settings;
  CLI::App *c_orbits = nullptr, *c_orbit = nullptr, *c_explore = nullptr, *c_sim = nullptr, *c_val = nullptr,
           *c_bench = nullptr, *c_fig = nullptr, *c_resp = nullptr, *c_settings = nullptr;
};

// Parses argv and runs; CLI11's own errors exit 2 (0 for --help, --version).
int Main(int argc, char** argv);

}  // namespace nsmodal::cli
