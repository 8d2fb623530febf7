#include "command_line.h"

#include <csignal>
#include <iostream>
#include <new>

#include "nsmodal/atlas.h"
#include "nsmodal/error.h"
#include "nsmodal/simulate_settings.h"
#include "nsmodal/validate_settings.h"
#include "nsmodal/input_checks.h"
#include "nsmodal/output.h"
#include "nsmodal/stop.h"

namespace nsmodal::cli {
namespace {

// " [m] (default 0.01; scene key simulate.sample_dt)": the help's tail, from the table.
template <class Options>
std::string HelpOf(const SettingTable<Options>& table, const Setting<Options>& s) {
  std::string help = s.info.doc;
  if (!s.info.unit.empty()) help += " [" + s.info.unit + "]";
  const SettingValue d = table.Default(s);
  help += " (default " + FormatSettingValue(d);
  const std::string key = table.SceneField(s.info);
  if (!key.empty()) help += "; scene key " + key;
  return help + ")";
}

// A flag for every setting of `table` that `command` takes: each value given
// goes into `flags` with the flag's name as its origin (settings.h).
template <class Options>
void AddSettingFlags(CLI::App* app, const std::string& command, const SettingTable<Options>& table,
                     SettingPatch& flags) {
  for (const Setting<Options>& s : table.settings()) {
    const SettingInfo& info = s.info;
    if (info.flag.empty() || !info.Takes(command)) continue;
    const std::string help = HelpOf(table, s);
    auto store = [&flags, name = info.name, flag = info.flag](SettingValue v) {
      flags[name] = {std::move(v), flag, SettingSource::kFlag};
    };
    switch (info.kind) {
      case SettingKind::kReal:
        app->add_option_function<double>(info.flag, store, help);
        break;
      case SettingKind::kInteger:  // read as a real: WholeNumberOf refuses 1.5 naming the flag
        app->add_option_function<double>(info.flag, store, help)->type_name("INT");
        break;
      case SettingKind::kText:
        app->add_option_function<std::string>(info.flag, store, help);
        break;
      case SettingKind::kRealList:
        app->add_option_function<std::vector<double>>(info.flag, store, help)->expected(1, kMaxDofs);
        break;
      case SettingKind::kIntegerList:
        app->add_option_function<std::vector<double>>(info.flag, store, help)->expected(1, 1000)->type_name("INT");
        break;
      case SettingKind::kTextList:
        app->add_option_function<std::vector<std::string>>(info.flag, store, help)->expected(1, 1000);
        break;
    }
  }
}

// "error: what" on stderr; the exit status.
int Failed(const std::exception& e, int status) {
  std::cerr << "error: " << e.what() << "\n";
  return status;
}

// SIGINT and SIGTERM ask the work to stop at its next poll (stop.h); the
// handler is reset by its first call, so a second signal ends the process at
// once (a stuck run can still be killed with a second Ctrl-C).
void InstallStopHandlers() {
  struct sigaction action {};
  action.sa_handler = [](int signal) { RequestStop(signal); };
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND | SA_RESTART;
  for (int signal : {SIGINT, SIGTERM}) sigaction(signal, &action, nullptr);
}

void AddFormat(CLI::App* app, std::string& format) {
  app->add_option("--format", format, "Tables as csv (default) or hdf5 (NAME.h5: a dataset per column, for large work)");
}

}  // namespace

CommandLine::CommandLine() {
  app.require_subcommand(1);
  app.set_version_flag("--version", "nsmodal " NSMODAL_VERSION);

  c_orbits = app.add_subcommand("orbits", "Potential and admissible orbits over a period grid (CSV)");
  c_orbits->add_option("scene", orbits.scene, "Scene file (TOML)")->required();
  c_orbits->add_option("--impacts", orbits.impacts, "Impacts per period (1 or 2), all on contact 1")->default_val(1);
  c_orbits->add_option("--sequence", orbits.sequence,
                       "The contact of each impact, e.g. 1,2 (contacts numbered from 1 as written; 1 or 2 impacts)");
  c_orbits->add_option("--period", orbits.period, "Period grid FROM:TO:STEP")->required();
  c_orbits->add_option("--out", orbits.out, "Output directory")->required();
  c_orbits->add_option("--threads", orbits.threads, "Worker threads (0: all cores)")->default_val(0)->check(CLI::Range(0, kMaxThreads));
  AddFormat(c_orbits, orbits.format);
  c_orbits->add_option("--modes", orbits.modes,
                       "Analyse the first K linear modes only (modal truncation; a column bounds what the others carry)");

  c_orbit = app.add_subcommand("orbit", "Every potential orbit at one period");
  c_orbit->add_option("scene", orbit.scene, "Scene file (TOML)")->required();
  c_orbit->add_option("--impacts", orbit.impacts, "Impacts per period (1 or 2), all on contact 1")->default_val(1);
  c_orbit->add_option("--sequence", orbit.sequence,
                      "The contact of each impact, e.g. 1,2 (contacts numbered from 1 as written; 1 or 2 impacts)");
  c_orbit->add_option("--period", orbit.period, "Period T")->required();
  c_orbit->add_flag("--json", orbit.json, "Print JSON {\"orbits\": [...]}");

  c_explore = app.add_subcommand("explore", "Exploratory search for 3 or more impacts per period (section 2.3)");
  c_explore->add_option("scene", explore.scene, "Scene file (TOML)")->required();
  c_explore->add_option("--impacts", explore.impacts, "Impacts per period (3 to 6)")->default_val(3);
  c_explore->add_option("--period", explore.period, "Period grid FROM:TO:STEP")->required();
  c_explore->add_option("--grid", explore.grid, "Grid nodes per impact-time axis")->default_val(24);
  c_explore->add_option("--sequence", explore.sequence, "The contact of each impact, e.g. 1,2,1 (sets --impacts)");
  c_explore->add_flag("--json", explore.json, "Print JSON");
  c_explore->add_option("--follow", explore.follow,
                        "FROM:TO:STEP: follow each admissible new orbit's family in T over [FROM, TO] (odd m)");

  c_sim = app.add_subcommand("simulate", "Simulate an initial condition (exact, cvode or moreau-jean)");
  c_sim->add_option("scene", simulate.scene, "Scene file (TOML) with a [simulate] table")->required();
  c_sim->add_option("--out", simulate.out, "Output directory")->required();
  AddFormat(c_sim, simulate.format);
  AddSettingFlags(c_sim, "simulate", SimulateSettings(), simulate.flags);

  c_val = app.add_subcommand("validate", "Validate analytic orbits by long simulations (batch)");
  c_val->add_option("scene", validate.scene, "Scene file (TOML); an optional [validate] table")->required();
  c_val->add_option("--out", validate.out, "Output directory")->required();
  AddFormat(c_val, validate.format);
  AddSettingFlags(c_val, "validate", ValidateSettings(), validate.flags);

  c_resp = app.add_subcommand("response", "Forced, damped response curves beside the nonsmooth modes (CSV, charts)");
  c_resp->add_option("scene", response.scene, "Scene file (TOML) with damping or e < 1 and a [forcing] table")->required();
  c_resp->add_option("--out", response.out, "Output directory")->required();
  c_resp->add_option("--impacts", response.impacts, "Impacts per response period m (0: the linear response)")->default_val(1);
  c_resp->add_option("--sequence", response.sequence, "The contact of each impact, e.g. 1,2 (sets --impacts; default: every impact on contact 1)");
  c_resp->add_option("--periods", response.periods, "Forcing periods per response period n")->default_val(1);
  c_resp->add_option("--frequency", response.frequency, "Grid FROM:TO:STEP of w, or w (default: the scene's)");
  c_resp->add_option("--amplitude", response.amplitude, "Grid FROM:TO:STEP of max|f_i|, or levels a,b,c (default: the scene's)");
  c_resp->add_option("--validate", response.validate, "Simulate every point this many periods (0: no validation)")->default_val(0)->check(CLI::Range(0, 100000000));
  c_resp->add_option("--integrators", response.integrators, "Integrators of --validate: exact, cvode, moreau-jean")->expected(1, 3);
  c_resp->add_option("--threads", response.threads, "Worker threads of --validate (0: all cores)")->default_val(0)->check(CLI::Range(0, kMaxThreads));

  c_cont = app.add_subcommand("continue", "A forced response followed in any parameter of the scene (gap, masses[1], "
                                          "restitution, ...), with its special points (CSV)");
  c_cont->add_option("scene", cont.scene, "Scene file (TOML) with damping or e < 1 and a [forcing] table")->required();
  c_cont->add_option("--parameter", cont.parameter, "The parameter, by its scene key: frequency, amplitude, gap, "
                     "restitution, contact[j].gap, contact[j].restitution, masses[i], springs[i], damping_ratios[i], "
                     "rayleigh_damping[k]")->required();
  c_cont->add_option("--range", cont.range, "FROM:TO or FROM:TO:STEP of the parameter (STEP: the largest step and the "
                     "spacing of the fixed values solved; default (TO - FROM) / 300)")->required();
  c_cont->add_option("--out", cont.out, "Output directory")->required();
  c_cont->add_option("--impacts", cont.impacts, "Impacts per response period m (0: the linear response)")->default_val(1);
  c_cont->add_option("--sequence", cont.sequence, "The contact of each impact, e.g. 1,2 (sets --impacts)");
  c_cont->add_option("--periods", cont.periods, "Forcing periods per response period n")->default_val(1);
  c_cont->add_option("--period", cont.period, "A scene with no [forcing]: the free 1-impact family's period grid "
                     "FROM:TO:STEP, its transitions followed in the parameter (transitions.csv)");
  c_cont->add_option("--second", cont.second, "A second parameter: the curves of the --follow points in both "
                     "(curve.csv instead of continuation.csv)");
  c_cont->add_option("--second-range", cont.second_range, "FROM:TO or FROM:TO:STEP of the second parameter");
  c_cont->add_option("--follow", cont.follow, "With --second: the special point followed: fold, period-doubling "
                     "or grazing");

  c_bench = app.add_subcommand("bench", "Speed against accuracy of the integrators, and grazing failures");
  c_bench->add_option("scene", bench.scene, "Scene file (the paper's system: configs/paper.toml)")->required();
  c_bench->add_option("--out", bench.out, "Output directory")->required();
  c_bench->add_flag("--quick", bench.quick, "Fewer settings and a 100-period long case");

  c_fig = app.add_subcommand("figures", "Redraw the paper's Figs. 2-15 (PNG, SVG and CSV) with stability");
  c_fig->add_option("scene", figures.scene, "Scene file (the paper's system: configs/paper.toml)")->required();
  c_fig->add_option("--out", figures.out, "Output directory")->required();
  c_fig->add_option("--period", figures.period, "FROM:TO:STEP of the 1-ipp and 2-ipp sweeps (default 0.01:4 T_max:0.01)");
  c_fig->add_option("--threads", figures.threads, "Worker threads (0: all cores)")->default_val(0)->check(CLI::Range(0, kMaxThreads));

  c_settings = app.add_subcommand("settings", "Every setting of simulate and validate: scene key, flag, Python keyword, "
                                              "default, unit, doc");
  c_settings->add_flag("--json", settings.json, "Print a JSON list of objects");
}

namespace {

// An --impacts given with --sequence must agree with the sequence's length,
// 1 too (one left at its default defers to the sequence, as in Python).
void ImpactsGivenAgree(const CLI::App* command, int impacts, const std::optional<std::string>& sequence) {
  if (!*command || !sequence || command->count("--impacts") == 0) return;
  CheckImpactsAgree(impacts, static_cast<int>(ParseValues(*sequence, "--sequence").size()), *sequence, "--impacts",
                    false);
}

}  // namespace

int CommandLine::Run() const {
  try {
    ImpactsGivenAgree(c_orbits, orbits.impacts, orbits.sequence);
    ImpactsGivenAgree(c_orbit, orbit.impacts, orbit.sequence);
    ImpactsGivenAgree(c_explore, explore.impacts, explore.sequence);
    ImpactsGivenAgree(c_resp, response.impacts, response.sequence);
    ImpactsGivenAgree(c_cont, cont.impacts, cont.sequence);
    int status = 1;
    if (*c_orbits) status = RunOrbits(orbits);
    if (*c_orbit) status = RunOrbit(orbit);
    if (*c_explore) status = RunExplore(explore);
    if (*c_sim) status = RunSimulate(simulate);
    if (*c_val) status = RunValidate(validate);
    if (*c_bench) status = RunBench(bench);
    if (*c_resp) status = RunResponse(response);
    if (*c_cont) status = RunContinue(cont);
    if (*c_fig) status = RunFigures(figures);
    if (*c_settings) status = RunSettings(settings);
    report::CheckStdout();
    return status;
  } catch (const Stopped& e) {
    // The results this run had written were removed as the work unwound
    // (output.h); 128 + the signal, as a shell reports a process it killed.
    std::cerr << "error: " << e.what() << ": stopped, no result written\n";
    return 128 + e.signal();
  } catch (const InputError& e) {
    return Failed(e, 2);
  } catch (const report::OutputError& e) {
    return Failed(e, 5);
  } catch (const std::bad_alloc&) {
    std::cerr << "error: out of memory: the run asked for more than this machine has (a smaller grid, fewer "
                 "samples or fewer periods)\n";
    return 1;
  } catch (const std::exception& e) {
    return Failed(e, 1);
  }
}

int Main(int argc, char** argv) {
  InstallStopHandlers();
  CommandLine cl;
  try {
    cl.app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every refused command line exits 2.
    return cl.app.exit(e) == 0 ? 0 : 2;
  }
  return cl.Run();
}

}  // namespace nsmodal::cli
