// libFuzzer target: the command line's argument handling. The input is split
// at NUL bytes into arguments after "nsmodal"; the command line is parsed
// (CLI11 with every subcommand's flags and checks) and the values that are
// parsed later (period grids, integrator names) are parsed too. Commands are
// not run: a fuzzed command line must not write files or start long work.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "command_line.h"
#include "nsmodal/atlas.h"
#include "nsmodal/error.h"
#include "nsmodal/simulate_settings.h"
#include "nsmodal/validate_settings.h"

namespace {

template <class F>
void Try(F&& f) {
  try {
    f();
  } catch (const nsmodal::InputError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> args{"nsmodal"};
  std::string current;
  for (std::size_t i = 0; i < size && args.size() < 64; ++i) {
    if (data[i] == 0) {
      args.push_back(current);
      current.clear();
    } else {
      current.push_back(static_cast<char>(data[i]));
    }
  }
  if (args.size() < 64) args.push_back(current);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  nsmodal::cli::CommandLine cl;
  try {
    cl.app.parse(static_cast<int>(argv.size()), argv.data());
  } catch (const CLI::ParseError&) {
    return 0;
  }
  for (const std::string* period : {&cl.orbits.period, &cl.explore.period}) {
    Try([&] { nsmodal::PeriodGrid::Parse(*period); });
  }
  // The settings' flags resolved and checked as the commands do (settings.h).
  Try([&] {
    const auto c = nsmodal::ValidateSettings().Resolve({&cl.validate.flags});
    if (!c.options.period.empty()) nsmodal::PeriodGrid::Parse(c.options.period, c.names("period"));
    c.options.options.Validate(c.names);
  });
  Try([&] {
    const auto c = nsmodal::SimulateSettings().Resolve({&cl.simulate.flags});
    c.options.options.Validate(c.names);
  });
  if (cl.figures.period) Try([&] { nsmodal::PeriodGrid::Parse(*cl.figures.period); });
  for (const auto* grid : {&cl.response.frequency, &cl.response.amplitude}) {
    if (*grid && (*grid)->find(':') != std::string::npos) Try([&] { nsmodal::PeriodGrid::Parse(**grid); });
  }
  for (const std::string& name : cl.response.integrators) Try([&] { nsmodal::ParseIntegrator(name, "--integrators"); });
  return 0;
}
