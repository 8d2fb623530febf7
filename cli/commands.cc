#include "commands.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <mutex>
#include <optional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "nsmodal/error.h"
#include "nsmodal/explore.h"
#include "nsmodal/gnuplot.h"
#include "nsmodal/modal_basis.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/output.h"
#include "nsmodal/parallel.h"
#include "nsmodal/scene.h"
#include "nsmodal/simulate.h"
#include "nsmodal/stability.h"
#include "nsmodal/validate.h"
#include "nsmodal/transitions.h"
#include "nsmodal/two_impact.h"
#include "nsmodal/work_precision.h"
#include "common.h"

namespace nsmodal::cli {
namespace {

double ParseNumber(const std::string& s, const std::string& field, const std::string& whole) {
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != s.size() || s.empty() || !std::isfinite(v)) {
    throw InputError(field, "expects FROM:TO:STEP with numbers, got '" + whole + "'");
  }
  return v;
}

void CheckImpacts(int impacts) {
  if (impacts != 1 && impacts != 2) {
    throw InputError("--impacts", "orbits and orbit compute 1 or 2 impacts per period, got " +
                                      std::to_string(impacts) + " (use 'nsmodal explore' for 3 or more)");
  }
}

void CheckT2Step(double step) {
  if (!(step > 0.0) || !std::isfinite(step)) throw InputError("--t2-step", "must be positive, got " + FormatValue(step));
}

void WriteOrbitHeader(std::ostream& os, int n) {
  os << "T,t2,energy,potential,admissible,periodicity_residual,nc2_residual,nc3_margin,degenerate";
  for (int i = 1; i <= n; ++i) os << ",x" << i;
  for (int i = 1; i <= n; ++i) os << ",v" << i;
  os << ",stable,max_multiplier";
  for (int k = 1; k <= 2 * n; ++k) os << ",mu" << k << "_re,mu" << k << "_im";
  os << "\n";
}

void WriteOrbitRow(std::ostream& os, const Orbit& o, const std::optional<Stability>& s) {
  os << o.period << ",";
  if (!o.times.empty()) os << o.times[0];
  os << "," << o.energy << "," << o.potential << "," << o.admissible << "," << o.periodicity_residual << ","
     << o.nc2_residual << "," << o.max_excess << "," << o.degenerate;
  for (int i = 0; i < o.z0.size(); ++i) os << "," << o.z0[i];
  if (s) {
    os << "," << s->stable << "," << s->max_modulus;
    for (int k = 0; k < s->multipliers.size(); ++k) {
      os << "," << s->multipliers[k].real() << "," << s->multipliers[k].imag();
    }
  } else {
    os << ",,";
    for (int k = 0; k < o.z0.size(); ++k) os << ",,";
  }
  os << "\n";
}

nlohmann::json OrbitJson(const Orbit& o, const std::optional<Stability>& s = std::nullopt) {
  const int n = static_cast<int>(o.z0.size() / 2);
  std::vector<double> x(o.z0.data(), o.z0.data() + n), v(o.z0.data() + n, o.z0.data() + 2 * n);
  nlohmann::json j{{"impacts", o.impacts},
                   {"T", o.period},
                   {"impact_times", o.times},
                   {"energy", o.energy},
                   {"potential", o.potential},
                   {"admissible", o.admissible},
                   {"degenerate", o.degenerate},
                   {"periodicity_residual", o.periodicity_residual},
                   {"nc2_residual", o.nc2_residual},
                   {"nc3_margin", std::isfinite(o.max_excess) ? nlohmann::json(o.max_excess) : nlohmann::json()},
                   {"x", x},
                   {"v", v},
                   {"reason", o.reason}};
  j["t2"] = o.times.empty() ? nlohmann::json() : nlohmann::json(o.times[0]);
  if (s) {
    j["stable"] = s->stable;
    j["max_multiplier"] = s->max_modulus;
    j["multipliers"] = nlohmann::json::array();
    for (int k = 0; k < s->multipliers.size(); ++k) {
      j["multipliers"].push_back({s->multipliers[k].real(), s->multipliers[k].imag()});
    }
  }
  return j;
}

}  // namespace

std::function<void(long, long)> ProgressBar(const std::string& label) {
  if (!isatty(STDERR_FILENO)) return {};
  return [label](long done, long count) {
    const int width = 40;
    const int filled = count > 0 ? static_cast<int>(width * done / count) : width;
    std::fprintf(stderr, "\r%s [%s%s] %ld/%ld", label.c_str(), std::string(filled, '#').c_str(),
                 std::string(width - filled, '.').c_str(), done, count);
    if (done == count) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  };
}

// Floquet multipliers of a potential orbit (stability.h); degenerate (bridge)
// orbits included: their family is a continuum, so one more multiplier is 1.
std::optional<Stability> StabilityOf(const AnalysisBasis& b, const Orbit& o) {
  if (!o.potential) return std::nullopt;
  return OrbitStability(b, o);
}

std::vector<double> PeriodRange::Values() const {
  std::vector<double> out;
  const long cells = std::lround(std::floor((to - from) / step + 1e-9));
  for (long j = 0; j <= cells; ++j) out.push_back(from + j * step);
  return out;
}

PeriodRange ParsePeriodRange(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream ss(text);
  for (std::string p; std::getline(ss, p, ':');) parts.push_back(p);
  if (parts.size() != 3) throw InputError("--period", "expects FROM:TO:STEP, got '" + text + "'");
  PeriodRange r{ParseNumber(parts[0], "--period", text), ParseNumber(parts[1], "--period", text),
                ParseNumber(parts[2], "--period", text)};
  if (!(r.from > 0.0)) throw InputError("--period", "FROM must be positive, got " + FormatValue(r.from));
  if (!(r.to >= r.from)) throw InputError("--period", "TO must be >= FROM, got '" + text + "'");
  if (!(r.step > 0.0)) throw InputError("--period", "STEP must be positive, got " + FormatValue(r.step));
  if ((r.to - r.from) / r.step > 1e8) {
    throw InputError("--period", "more than 1e8 periods requested by '" + text + "'");
  }
  return r;
}

int RunOrbits(const OrbitsArgs& a) {
  CheckImpacts(a.impacts);
  CheckT2Step(a.t2_step);
  const PeriodRange range = ParsePeriodRange(a.period);
  const AnalysisBasis b(LoadScene(a.scene).model);
  const report::OutputDir dir = report::OutputDir::Prepare(a.out, {"orbits.csv", "transitions.csv"});
  const std::vector<double> periods = range.Values();
  std::vector<std::vector<Orbit>> results(periods.size());
  std::vector<std::vector<std::optional<Stability>>> stability(periods.size());
  TwoImpactOptions two;
  two.t2_step = a.t2_step;
  ParallelFor(
      static_cast<long>(periods.size()), a.threads,
      [&](long i) {
        if (a.impacts == 1) {
          results[i].push_back(OneImpactOrbit(b, periods[i]));
        } else {
          results[i] = TwoImpactOrbits(b, periods[i], two);
        }
        for (const Orbit& o : results[i]) stability[i].push_back(StabilityOf(b, o));
      },
      ProgressBar(a.impacts == 1 ? "1-ipp orbits" : "2-ipp orbits"));
  report::ResultFile out(dir, "orbits.csv");
  WriteOrbitHeader(out.stream(), b.n);
  long rows = 0, admissible = 0;
  for (std::size_t i = 0; i < results.size(); ++i) {
    for (std::size_t k = 0; k < results[i].size(); ++k) {
      WriteOrbitRow(out.stream(), results[i][k], stability[i][k]);
      ++rows;
      admissible += results[i][k].admissible;
    }
  }
  out.Commit();
  std::cout << "wrote " << rows << " orbits (" << admissible << " admissible) to " << a.out << "/orbits.csv\n";
  if (a.impacts == 1) {
    std::vector<bool> adm;
    for (const auto& list : results) adm.push_back(list.front().admissible);
    const std::vector<Transition> transitions = OneImpactTransitions(b, periods, adm);
    report::ResultFile tr(dir, "transitions.csv");
    tr << "T,kind,energy\n";
    for (const Transition& t : transitions) tr << t.period << "," << ToString(t.kind) << "," << t.energy << "\n";
    tr.Commit();
    std::cout << "wrote " << transitions.size() << " transitions to " << a.out << "/transitions.csv\n";
  }
  return 0;
}

int RunBench(const BenchArgs& a) {
  const Scene scene = LoadScene(a.scene);
  const Model paper = PaperModel();
  if (scene.model.mass != paper.mass || scene.model.stiffness != paper.stiffness ||
      scene.model.contact != paper.contact || scene.model.gap != paper.gap) {
    throw InputError("scene", "the bench cases (a stable orbit at T = 7.5, the grazing and singular transitions at "
                              "9.127 and 4.834, a Zeno start) are defined on the paper's system; use "
                              "configs/paper.toml");
  }
  const report::OutputDir dir =
      report::OutputDir::Prepare(a.out, {"work_precision.csv", "grazing.csv", "work_precision_*"});
  WorkPrecisionOptions opt;
  opt.quick = a.quick;
  opt.progress = ProgressBar(a.quick ? "work-precision (quick)" : "work-precision");
  const std::vector<WorkPrecisionRow> rows = RunWorkPrecision(opt);
  report::ResultFile csv(dir, "work_precision.csv");
  csv << "case,integrator,setting,error,cpu_s,impacts,steps\n";
  for (const WorkPrecisionRow& r : rows) {
    csv << r.case_name << "," << r.integrator << "," << r.setting << "," << r.error << "," << r.cpu_s << ","
        << r.impacts << "," << r.steps << "\n";
  }
  csv.Commit();
  const std::vector<GrazingRow> grazing = RunGrazingFailures(opt);
  report::ResultFile gcsv(dir, "grazing.csv");
  gcsv << "delta,side,clearance,integrator,setting,impacts,expected_impacts\n";
  for (const GrazingRow& r : grazing) {
    gcsv << r.delta << "," << r.side << "," << r.clearance << "," << r.integrator << "," << r.setting << ","
         << r.impacts << "," << r.expected_impacts << "\n";
  }
  gcsv.Commit();
  // One log-log chart per case: error against CPU time, a line per integrator
  // (the reference setting itself, error 0, has no place on a log scale).
  std::vector<std::string> case_names, integrators;
  for (const WorkPrecisionRow& r : rows) {
    if (std::find(case_names.begin(), case_names.end(), r.case_name) == case_names.end()) {
      case_names.push_back(r.case_name);
    }
    if (std::find(integrators.begin(), integrators.end(), r.integrator) == integrators.end()) {
      integrators.push_back(r.integrator);
    }
  }
  std::string integrator_list;
  for (const std::string& i : integrators) integrator_list += (integrator_list.empty() ? "" : " ") + i;
  int failed_charts = 0;
  for (const std::string& name : case_names) {
    std::ostringstream body;
    body << "set datafile separator ','\nset logscale xy\nset format y '10^{%T}'\nset format x '10^{%T}'\n"
         << "set xlabel 'CPU time per run (s)'\nset ylabel 'relative error of the final state (vs exact, root\\_tol 1e-14)'\n"
         << "set title 'work-precision: " << name << "'\nset key outside right\nset grid\n"
         << "plot for [i in '" << integrator_list << "'] 'work_precision.csv' "
         << "using (strcol(1) eq '" << name << "' && strcol(2) eq i && $4 > 0 ? $5 : 1/0):4 "
         << "with linespoints lw 2 pt 7 title i\n";
    const report::ChartStatus chart = report::DrawChart(dir, "work_precision_" + name, body.str());
    if (!chart.drawn) {
      std::cerr << "work_precision_" << name << " not drawn: " << chart.message << "\n";
      ++failed_charts;
    }
  }
  // The tables a person reads: error and cost per case, and the grazing limits.
  std::cout << std::left << std::setw(13) << "case" << std::setw(13) << "integrator" << std::setw(16) << "setting"
            << std::right << std::setw(10) << "error" << std::setw(11) << "cpu_s" << std::setw(9) << "impacts"
            << std::setw(12) << "steps" << "\n";
  for (const WorkPrecisionRow& r : rows) {
    std::cout << std::left << std::setw(13) << r.case_name << std::setw(13) << r.integrator << std::setw(16)
              << r.setting << std::right << std::scientific << std::setprecision(2) << std::setw(10) << r.error
              << std::setw(11) << r.cpu_s << std::defaultfloat << std::setw(9) << r.impacts << std::setw(12)
              << r.steps << "\n";
  }
  std::cout << "\ngrazing (T_G +- delta, one period): the shallowest excursion past d turned into the right impacts,\n"
               "and the smallest clearance below d without a spurious impact (inf: wrong at the largest tried)\n";
  std::cout << std::left << std::setw(13) << "integrator" << std::setw(16) << "setting" << std::right << std::setw(14)
            << "excursion" << std::setw(14) << "clearance" << "\n";
  for (const GrazingLimit& l : SummarizeGrazing(grazing)) {
    std::cout << std::left << std::setw(13) << l.integrator << std::setw(16) << l.setting << std::right
              << std::scientific << std::setprecision(2) << std::setw(14) << l.shallowest_excursion << std::setw(14)
              << l.smallest_clearance << std::defaultfloat << "\n";
  }
  std::cout.flush();
  std::cerr << "wrote " << rows.size() << " work-precision rows and " << grazing.size() << " grazing rows to " << a.out
            << " (work_precision.csv, grazing.csv, work_precision_*.png/svg)\n";
  if (failed_charts) throw report::OutputError(std::to_string(failed_charts) + " chart(s) could not be drawn");
  return 0;
}

int RunValidate(const ValidateArgs& a) {
  const Scene scene = LoadScene(a.scene);
  const AnalysisBasis b(scene.model);
  const ValidateSection& sec = scene.validate;
  const std::string period_text = a.period ? *a.period : sec.period ? *sec.period : "";
  if (period_text.empty()) throw InputError("--period", "is missing: give it with --period or validate.period");
  const PeriodRange range = ParsePeriodRange(period_text);
  const std::vector<int> impacts = a.impacts ? *a.impacts : sec.impacts ? *sec.impacts : std::vector<int>{1, 2};
  for (int m : impacts) {
    if (m != 1 && m != 2) throw InputError("--impacts", "takes 1 and/or 2, got " + std::to_string(m));
  }
  ValidateOptions opt;
  opt.periods = a.periods ? *a.periods : sec.periods ? *sec.periods : 1000;
  opt.integrators.clear();
  for (const std::string& name :
       a.integrators ? *a.integrators : sec.integrators ? *sec.integrators : std::vector<std::string>{"exact"}) {
    opt.integrators.push_back(ParseIntegrator(name, a.integrators ? "--integrators" : "validate.integrators"));
  }
  opt.simulate.rtol = a.rtol ? *a.rtol : 1e-10;
  opt.simulate.atol = a.atol ? *a.atol : 1e-12;
  opt.simulate.step = a.step ? *a.step : 1e-4;
  opt.Validate();
  const report::OutputDir dir = report::OutputDir::Prepare(a.out, {"validation.csv", "summary.json"});

  // The potential orbits of the grid, admissible or not.
  const std::vector<double> periods = range.Values();
  std::vector<std::vector<Orbit>> per_period(periods.size());
  ParallelFor(static_cast<long>(periods.size()), a.threads, [&](long i) {
    for (int m : impacts) {
      if (m == 1) {
        Orbit o = OneImpactOrbit(b, periods[i]);
        if (o.potential) per_period[i].push_back(o);
      } else {
        for (Orbit& o : TwoImpactOrbits(b, periods[i])) {
          if (o.potential) per_period[i].push_back(o);
        }
      }
    }
  });
  std::vector<Orbit> orbits;
  for (auto& list : per_period) orbits.insert(orbits.end(), list.begin(), list.end());
  const std::vector<OrbitValidation> results = ValidateOrbits(scene.model, orbits, opt, ProgressBar("validate"));

  report::ResultFile csv(dir, "validation.csv");
  csv << "T,t2,impacts_per_period,integrator,admissible,stable,max_multiplier,predicted_growth,measured_growth,"
         "deviation_1,deviation_10,deviation_100,deviation_final,periods_run,impacts,first_period_impacts,"
         "impact_time_error,max_penetration,manifold_distance,perturbed_manifold_distance,perturbed_amplification,"
         "perturbed_growth,perturbed_periods,energy_drift,wall_time_s,consistent,reason\n";
  nlohmann::json summary;
  std::map<std::string, std::array<long, 3>> counts;  // checked, consistent, inconsistent
  std::vector<const OrbitValidation*> inconsistent, admissible_exact_failures;
  for (const OrbitValidation& v : results) {
    const std::string name = ToString(v.integrator);
    csv << v.orbit.period << ",";
    if (!v.orbit.times.empty()) csv << v.orbit.times[0];
    csv << "," << v.orbit.impacts << "," << name << "," << v.orbit.admissible << "," << v.stability.stable << ","
        << v.stability.max_modulus << "," << v.stability.growth_per_period << "," << v.measured_growth << ","
        << v.DeviationAt(1) << "," << v.DeviationAt(10) << "," << v.DeviationAt(100) << ","
        << (v.deviation.empty() ? -1.0 : v.deviation.back()) << "," << v.deviation.size() << "," << v.impacts << ","
        << v.first_period_impacts << "," << v.impact_time_error << "," << v.max_penetration << ","
        << v.manifold_distance << "," << v.perturbed_manifold_distance << "," << v.perturbed_amplification << ","
        << v.perturbed_growth << "," << v.perturbed_periods << "," << v.energy_drift << ","
        << v.wall_time_s << "," << v.consistent << ",\"" << v.reason << "\"\n";
    auto& c = counts[name];
    ++c[0];
    ++c[v.consistent ? 1 : 2];
    if (!v.consistent) inconsistent.push_back(&v);
    if (!v.consistent && v.orbit.admissible && v.integrator == Integrator::kExact) admissible_exact_failures.push_back(&v);
  }
  auto describe = [](const OrbitValidation& v) {
    return nlohmann::json{{"T", v.orbit.period},
                          {"t2", v.orbit.times.empty() ? nlohmann::json() : nlohmann::json(v.orbit.times[0])},
                          {"integrator", ToString(v.integrator)},
                          {"admissible", v.orbit.admissible},
                          {"stable", v.stability.stable},
                          {"deviation_final", v.deviation.empty() ? -1.0 : v.deviation.back()},
                          {"reason", v.reason}};
  };
  summary["orbits"] = orbits.size();
  summary["periods"] = opt.periods;
  for (const auto& [name, c] : counts) {
    summary["integrators"][name] = {{"checked", c[0]}, {"consistent", c[1]}, {"inconsistent", c[2]}};
  }
  summary["inconsistent"] = nlohmann::json::array();
  for (const OrbitValidation* v : inconsistent) summary["inconsistent"].push_back(describe(*v));
  // Worst stable admissible orbits per integrator: the largest final deviation.
  for (Integrator integrator : opt.integrators) {
    std::vector<const OrbitValidation*> stable;
    for (const OrbitValidation& v : results) {
      if (v.integrator == integrator && v.orbit.admissible && v.stability.stable && !v.deviation.empty()) {
        stable.push_back(&v);
      }
    }
    std::sort(stable.begin(), stable.end(),
              [](const auto* x, const auto* y) { return x->deviation.back() > y->deviation.back(); });
    nlohmann::json worst = nlohmann::json::array();
    for (std::size_t k = 0; k < std::min<std::size_t>(5, stable.size()); ++k) worst.push_back(describe(*stable[k]));
    summary["worst_stable"][ToString(integrator)] = worst;
  }
  // The off-family perturbation of the admissible orbits (exact integrator):
  // stable ones stay within a bounded factor, unstable ones grow at log|lambda|.
  long stable_runs = 0, rated = 0, rated_within = 0;
  double worst_amplification = 0.0, worst_rate_error = 0.0;
  for (const OrbitValidation& v : results) {
    if (v.integrator != Integrator::kExact || !v.orbit.admissible || v.perturbed_periods < 0) continue;
    if (v.stability.stable) {
      ++stable_runs;
      worst_amplification = std::max(worst_amplification, v.perturbed_amplification);
    } else if (v.perturbed_growth > 0.0) {
      const double err = std::abs(v.perturbed_growth / v.stability.growth_per_period - 1.0);
      ++rated;
      rated_within += err <= 0.05;
      worst_rate_error = std::max(worst_rate_error, err);
    }
  }
  summary["perturbation"] = {{"relative_size", opt.perturbation},
                             {"stable_orbits", stable_runs},
                             {"stable_worst_amplification", worst_amplification},
                             {"unstable_orbits_rated", rated},
                             {"unstable_rate_within_5_percent", rated_within},
                             {"unstable_worst_relative_rate_error", worst_rate_error}};
  csv.Commit();
  report::WriteResult(dir, "summary.json", summary.dump(2) + "\n");
  if (stable_runs + rated > 0) {
    std::cout << "perturbed by " << opt.perturbation << " |y| in the nontrivial Floquet subspace (exact): " << stable_runs
              << " stable orbits grew at most x" << worst_amplification << " over " << opt.periods << " periods; "
              << rated_within << "/" << rated << " unstable orbits grew within 5 % of log|lambda| (worst "
              << 100.0 * worst_rate_error << " %)\n";
  }
  std::cout << "validated " << orbits.size() << " orbits over " << opt.periods << " periods:";
  for (const auto& [name, c] : counts) std::cout << "  " << name << " " << c[1] << "/" << c[0] << " consistent";
  std::cout << "\nwrote " << a.out << "/validation.csv and " << a.out << "/summary.json\n";
  for (const OrbitValidation* v : inconsistent) {
    std::cout << "  inconsistent: T = " << v->orbit.period << (v->orbit.times.empty() ? "" : " t2 = " + FormatValue(v->orbit.times[0]))
              << " (" << ToString(v->integrator) << "): " << v->reason << "\n";
  }
  if (!admissible_exact_failures.empty()) {
    std::cerr << "error: " << admissible_exact_failures.size()
              << " admissible orbit(s) failed to validate with the exact integrator (see above)\n";
    return 4;
  }
  return 0;
}

int RunSimulate(const SimulateArgs& a) {
  const Scene scene = LoadScene(a.scene);
  const SimulateSection& sec = scene.simulate;
  SimulateOptions opt;
  auto pick = [](const auto& flag, const auto& table, auto fallback) { return flag ? *flag : table ? *table : fallback; };
  opt.integrator = ParseIntegrator(pick(a.integrator, sec.integrator, std::string("exact")),
                                   a.integrator ? "--integrator" : "simulate.integrator");
  opt.cvode_method = pick(a.method, sec.method, opt.cvode_method);
  opt.t_end = pick(a.t_end, sec.t_end, opt.t_end);
  opt.rtol = pick(a.rtol, sec.rtol, opt.rtol);
  opt.atol = pick(a.atol, sec.atol, opt.atol);
  opt.step = pick(a.step, sec.step, opt.step);
  opt.theta = pick(a.theta, sec.theta, opt.theta);
  opt.root_tol = pick(a.root_tol, sec.root_tol, opt.root_tol);
  opt.sample_dt = pick(a.sample_dt, sec.sample_dt, opt.sample_dt);
  const int n = scene.model.dofs();
  const auto x0v = a.x0 ? a.x0 : sec.initial_position;
  if (!x0v) throw InputError("simulate.initial_position", "is missing: give it in [simulate] or with --x0");
  const std::vector<double> v0v = a.v0 ? *a.v0 : sec.initial_velocity ? *sec.initial_velocity : std::vector<double>(n, 0.0);
  const Eigen::VectorXd x0 = Eigen::Map<const Eigen::VectorXd>(x0v->data(), static_cast<long>(x0v->size()));
  const Eigen::VectorXd v0 = Eigen::Map<const Eigen::VectorXd>(v0v.data(), static_cast<long>(v0v.size()));

  opt.Validate();
  Validate(scene.model);
  const report::OutputDir dir = report::OutputDir::Prepare(a.out, {"trajectory.csv", "impacts.csv", "summary.json"});
  report::ResultFile traj(dir, "trajectory.csv");
  report::ResultFile imp(dir, "impacts.csv");
  traj << "t";
  for (int i = 1; i <= n; ++i) traj << ",x" << i;
  for (int i = 1; i <= n; ++i) traj << ",v" << i;
  traj << ",energy\n";
  imp << "t";
  for (const char* when : {"before", "after"}) {
    for (int i = 1; i <= n; ++i) imp << ",x" << i << "_" << when;
    for (int i = 1; i <= n; ++i) imp << ",v" << i << "_" << when;
  }
  imp << "\n";
  const Model& m = scene.model;
  SimulationObserver obs;
  obs.on_sample = [&](double t, const Eigen::VectorXd& z) {
    traj << t;
    for (int i = 0; i < 2 * n; ++i) traj << "," << z[i];
    traj << "," << 0.5 * z.tail(n).dot(m.mass * z.tail(n)) + 0.5 * z.head(n).dot(m.stiffness * z.head(n)) << "\n";
  };
  obs.on_impact = [&](const ContactEvent& ev) {
    imp << ev.t;
    for (int i = 0; i < 2 * n; ++i) imp << "," << ev.before[i];
    for (int i = 0; i < 2 * n; ++i) imp << "," << ev.after[i];
    imp << "\n";
  };
  const auto bar = ProgressBar("simulate");
  if (bar) {
    obs.on_progress = [&](double t) { bar(static_cast<long>(1000.0 * t / opt.t_end), 1000); };
  }
  const SimulationSummary s = Simulate(m, x0, v0, opt, obs);
  if (bar) bar(1000, 1000);
  nlohmann::json j;
  j["integrator"] = ToString(opt.integrator);
  j["status"] = ToString(s.status);
  j["message"] = s.message;
  j["final_time"] = s.final_time;
  j["final_state"] = std::vector<double>(s.final_state.data(), s.final_state.data() + s.final_state.size());
  j["impacts"] = s.impacts;
  j["grazes"] = s.grazes;
  j["zeno_events"] = s.zeno_events;
  j["first_zeno_time"] = s.first_zeno_time >= 0.0 ? nlohmann::json(s.first_zeno_time) : nlohmann::json();
  j["sticking_phases"] = s.sticking_phases;
  j["sticking_time"] = s.sticking_time;
  j["initial_energy"] = s.initial_energy;
  j["final_energy"] = s.final_energy;
  j["energy_drift"] = s.energy_drift;
  j["wall_time_s"] = s.wall_time_s;
  j["steps"] = s.steps;
  j["settings"] = {{"t_end", opt.t_end}, {"rtol", opt.rtol}, {"atol", opt.atol}, {"method", opt.cvode_method},
                   {"step", opt.step}, {"theta", opt.theta}, {"root_tol", opt.root_tol}, {"sample_dt", opt.sample_dt}};
  traj.Commit();
  imp.Commit();
  report::WriteResult(dir, "summary.json", j.dump(2) + "\n");
  std::cout << ToString(opt.integrator) << ": t = " << s.final_time << ", " << s.impacts << " impacts, " << s.grazes
            << " grazes, " << s.zeno_events << " Zeno sequences, sticking " << s.sticking_time << ", energy drift "
            << s.energy_drift << ", " << s.wall_time_s << " s; wrote " << a.out << "/{trajectory.csv,impacts.csv,summary.json}\n";
  if (s.status != SimulationStatus::kFinished) {
    std::cerr << "error: simulation stopped: " << s.message << "\n";
    return 3;
  }
  return 0;
}

int RunOrbit(const OrbitArgs& a) {
  CheckImpacts(a.impacts);
  CheckT2Step(a.t2_step);
  if (!(a.period > 0.0) || !std::isfinite(a.period)) {
    throw InputError("--period", "must be positive, got " + FormatValue(a.period));
  }
  const AnalysisBasis b(LoadScene(a.scene).model);
  std::vector<Orbit> orbits;
  if (a.impacts == 1) {
    orbits.push_back(OneImpactOrbit(b, a.period));
  } else {
    TwoImpactOptions two;
    two.t2_step = a.t2_step;
    orbits = TwoImpactOrbits(b, a.period, two);
  }
  if (a.json) {
    nlohmann::json arr = nlohmann::json::array();
    for (const Orbit& o : orbits) arr.push_back(OrbitJson(o, StabilityOf(b, o)));
    std::cout << nlohmann::json{{"orbits", arr}}.dump(2) << "\n";
    return 0;
  }
  std::cout << std::setprecision(12);
  std::cout << orbits.size() << " potential orbit(s) with " << a.impacts << " impact(s) per period, T = " << a.period
            << "\n";
  for (std::size_t k = 0; k < orbits.size(); ++k) {
    const Orbit& o = orbits[k];
    std::cout << "\n#" << k + 1 << (o.admissible ? "  admissible" : "  NOT admissible")
              << (o.potential ? "" : " (not potential)") << (o.degenerate ? " (degenerate: bridge)" : "") << "\n";
    if (!o.times.empty()) std::cout << "  t2                    " << o.times[0] << "\n";
    std::cout << "  energy                " << o.energy << "\n"
              << "  periodicity residual  " << o.periodicity_residual << "\n"
              << "  NC2 residual          " << o.nc2_residual << "\n"
              << "  NC3 margin (max x_c-d) " << o.max_excess << "\n";
    std::cout << "  x(0) =";
    for (int i = 0; i < b.n; ++i) std::cout << " " << o.z0[i];
    std::cout << "\n  v(0+) =";
    for (int i = 0; i < b.n; ++i) std::cout << " " << o.z0[b.n + i];
    std::cout << "\n";
    if (const std::optional<Stability> s = StabilityOf(b, o)) {
      std::cout << "  " << (s->stable ? "stable" : "unstable") << ", Floquet multipliers";
      for (int k = 0; k < s->multipliers.size(); ++k) {
        std::cout << " " << s->multipliers[k].real() << (s->multipliers[k].imag() < 0 ? "-" : "+")
                  << std::abs(s->multipliers[k].imag()) << "i";
      }
      std::cout << "\n";
    }
    if (!o.reason.empty()) std::cout << "  " << o.reason << "\n";
  }
  return 0;
}

int RunExplore(const ExploreArgs& a) {
  if (a.grid < 4 || a.grid > 200) throw InputError("--grid", "must lie in [4, 200], got " + std::to_string(a.grid));
  const PeriodRange range = ParsePeriodRange(a.period);
  const AnalysisBasis b(LoadScene(a.scene).model);
  ExploreOptions opt;
  opt.impacts = a.impacts;
  opt.grid = a.grid;
  if (a.impacts < 3 || a.impacts > 6) {
    throw InputError("--impacts", "explore takes 3 to 6 impacts per period, got " + std::to_string(a.impacts) +
                                      " (use 'nsmodal orbits' for 1 or 2)");
  }
  const std::vector<double> periods = range.Values();
  std::vector<ExploreReport> parts(periods.size());
  ParallelFor(
      static_cast<long>(periods.size()), 0, [&](long i) { parts[i] = ExploreImpacts(b, {periods[i]}, opt); },
      ProgressBar("explore"));
  ExploreReport r;
  r.impacts = a.impacts;
  r.best_phi_new = INFINITY;
  for (const ExploreReport& p : parts) {
    r.samples += p.samples;
    for (auto [k, v] : p.kernel_dimension_histogram) r.kernel_dimension_histogram[k] += v;
    r.findings.insert(r.findings.end(), p.findings.begin(), p.findings.end());
    r.best_phi_new = std::min(r.best_phi_new, p.best_phi_new);
  }
  long repeated = 0, grazing = 0, fresh = 0, fresh_admissible = 0;
  for (const ExploreFinding& f : r.findings) {
    (f.kind == "new" ? fresh : f.kind == "grazing-contact" ? grazing : repeated) += 1;
    fresh_admissible += f.kind == "new" && f.orbit.admissible;
  }
  if (a.json) {
    nlohmann::json j;
    j["impacts"] = r.impacts;
    j["samples"] = r.samples;
    for (auto [k, v] : r.kernel_dimension_histogram) j["kernel_dimension_histogram"][std::to_string(k)] = v;
    j["findings"] = nlohmann::json::array();
    for (const ExploreFinding& f : r.findings) {
      nlohmann::json o = OrbitJson(f.orbit);
      o["kind"] = f.kind;
      o["kernel_dimension"] = f.kernel_dimension;
      o["grazing_ratio"] = f.grazing_ratio;
      j["findings"].push_back(o);
    }
    j["best_phi_new"] = r.best_phi_new;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << "m = " << r.impacts << ": " << r.samples << " grid samples over " << periods.size() << " periods\n";
  std::cout << "dim ker A_m " << (r.impacts % 2 ? "at grid samples" : "at roots found") << ":";
  for (auto [k, v] : r.kernel_dimension_histogram) std::cout << "  " << k << " -> " << v;
  std::cout << "\npotential orbits (cyclic shifts merged): " << repeated << " repeat a lower-m orbit, " << grazing
            << " have a grazing contact, " << fresh << " new (" << fresh_admissible << " admissible)\n";
  std::cout << "smallest defect away from repeated orbits: " << r.best_phi_new << "\n";
  std::cout << "conjecture (paper 2.3): dim ker = " << (r.impacts % 2 ? 1 : 2)
            << "; potential solutions only as degenerate lower-m orbits\n";
  for (const ExploreFinding& f : r.findings) {
    if (f.kind != "new") continue;
    std::cout << "  new: T = " << f.orbit.period << " times =";
    for (double t : f.orbit.times) std::cout << " " << t;
    std::cout << " energy = " << f.orbit.energy << " min/max |v_c-| = " << f.grazing_ratio
              << (f.orbit.admissible ? " admissible" : " not admissible") << "\n";
  }
  return 0;
}

}  // namespace nsmodal::cli
