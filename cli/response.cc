// nsmodal response: frequency- (or amplitude-) response curves of the
// forced, damped system, beside the nonsmooth modes of its conservative twin.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>

#include "commands.h"
#include "common.h"
#include "nsmodal/error.h"
#include "nsmodal/figures.h"
#include "nsmodal/output.h"
#include "nsmodal/response.h"
#include "nsmodal/scene.h"
#include "nsmodal/tables.h"
#include "nsmodal/validate.h"

namespace nsmodal::cli {
namespace {

bool IsGrid(const std::string& text) { return text.find(':') != std::string::npos; }

// "0.3" or "0.1,0.2,0.4": every value positive and finite.
std::vector<double> ParseValues(const std::string& text, const std::string& field) {
  std::vector<double> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !(v > 0.0) || !std::isfinite(v)) {
      throw InputError(field, "must be a positive number, a list of them (a,b,c) or a grid FROM:TO:STEP, got '" +
                                  text + "'");
    }
    out.push_back(v);
  }
  if (out.empty()) throw InputError(field, "is empty");
  return out;
}

}  // namespace

int RunResponse(const ResponseArgs& a) {
  const Scene scene = LoadScene(a.scene);
  const Model& model = scene.model;
  const bool frequency_grid = a.frequency && IsGrid(*a.frequency);
  const bool amplitude_grid = a.amplitude && IsGrid(*a.amplitude);
  if (frequency_grid == amplitude_grid) {
    throw InputError(a.frequency ? "--frequency" : "--amplitude",
                     "give exactly one of --frequency and --amplitude as a grid FROM:TO:STEP (the other as values, "
                     "or from the scene's [forcing])");
  }
  if (!model.forcing.HasHarmonic()) {
    throw InputError("forcing.amplitude", "is needed: the scene's [forcing] gives the direction of f cos(w t)");
  }
  ResponseOptions base;
  base.impacts = a.impacts;
  base.periods = a.periods;
  base.parameter = frequency_grid ? ResponseParameter::kFrequency : ResponseParameter::kAmplitude;
  base.grid = PeriodGrid::Parse(frequency_grid ? *a.frequency : *a.amplitude,
                                frequency_grid ? "--frequency" : "--amplitude");
  // The fixed parameter: its flag's values, else the scene's.
  std::vector<double> levels;
  if (frequency_grid) {
    levels = a.amplitude ? ParseValues(*a.amplitude, "--amplitude")
                         : std::vector<double>{model.forcing.amplitude.cwiseAbs().maxCoeff()};
  } else {
    levels = a.frequency ? ParseValues(*a.frequency, "--frequency") : std::vector<double>{model.forcing.frequency};
  }
  base.fixed = levels.front();
  FieldNames names;
  names.Set("impacts", "--impacts").Set("periods", "--periods").Set("frequency", "--frequency").Set("amplitude", "--amplitude");
  base.Validate(names);
  // --validate: every point simulated a.validate periods with each
  // integrator; its options checked now, before any work or file.
  ValidateOptions vopt;
  vopt.periods = std::max(a.validate, 1);
  vopt.integrators.clear();
  for (const std::string& name : a.integrators) vopt.integrators.push_back(ParseIntegrator(name, "--integrators"));
  vopt.threads = a.threads;
  const FieldNames vnames = FieldNames().Set("periods", "--validate").Set("integrators", "--integrators");
  vopt.Validate(vnames);
  const report::OutputDir dir = report::OutputDir::Prepare(
      a.out, {"response.csv", "response_points.csv", "backbone.csv", "response_validation.csv", "response_energy*",
              "response_max_xc*"});
  std::vector<report::ResponseRow> rows;
  std::vector<SpecialPoint> points;
  int branch_offset = 0;
  for (double level : levels) {
    ResponseOptions opt = base;
    opt.fixed = level;
    opt.progress = ProgressBar("response " + std::string(frequency_grid ? "a = " : "w = ") + FormatValue(level));
    const ResponseCurve curve = ComputeResponse(model, opt);
    for (std::size_t b = 0; b < curve.branches.size(); ++b) {
      for (const ForcedOrbit& o : curve.branches[b].points) rows.push_back({branch_offset + static_cast<int>(b) + 1, o});
      std::cout << "branch " << branch_offset + b + 1 << ": " << curve.branches[b].points.size() << " points; "
                << curve.branches[b].end << "\n";
    }
    for (SpecialPoint p : curve.points) {
      p.branch += branch_offset;
      points.push_back(p);
    }
    for (const std::string& note : curve.notes) std::cout << "note: " << note << "\n";
    branch_offset += static_cast<int>(curve.branches.size());
  }
  report::ResultFile out(dir, "response.csv");
  report::WriteCsv(out.stream(), report::ResponseColumns(model.dofs()), rows);
  out.Commit();
  report::ResultFile pts(dir, "response_points.csv");
  report::WriteCsv(pts.stream(), report::ResponsePointColumns(), points);
  pts.Commit();
  std::cout << "wrote " << rows.size() << " points on " << branch_offset << " branches to " << a.out
            << "/response.csv, " << points.size() << " special points to " << a.out << "/response_points.csv\n";
  bool backbone = false;
  if (frequency_grid) {
    // The nonsmooth mode of the conservative twin over the same frequencies.
    SweepOptions sopt;
    sopt.stability = StabilityPolicy::kAdmissible;
    sopt.progress = ProgressBar("backbone");
    // An (m, n) response has period n 2 pi / w: it meets the mode of period
    // T = n 2 pi / w, i.e. of frequency w / n.
    const double n = base.periods;
    const Sweep sweep = BackboneSweep(model, base.grid.from / n, base.grid.to / n, 2000, sopt);
    report::ResultFile bb(dir, "backbone.csv");
    std::vector<OrbitRecord> records;
    for (const auto& list : sweep.at) records.insert(records.end(), list.begin(), list.end());
    report::WriteCsv(bb.stream(), report::BackboneColumns(), records);
    bb.Commit();
    backbone = true;
    for (const SpecialPoint& p : points) {
      if (p.kind != SpecialKind::kPeak) continue;
      const double own = p.orbit.frequency / n;  // the response's own frequency 2 pi / P
      const std::optional<double> w = BackboneFrequency(model, sweep, p.orbit.energy, own);
      std::cout << "peak on branch " << p.branch + 1 << ": w = " << FormatValue(p.orbit.frequency)
                << (n > 1 ? " (w / n = " + FormatValue(own) + ")" : std::string()) << ", energy = "
                << FormatValue(p.orbit.energy);
      if (w) {
        std::cout << "; the nonsmooth mode at that energy: w = " << FormatValue(*w) << " (difference "
                  << FormatValue(own - *w) << ")\n";
      } else {
        std::cout << "; no admissible nonsmooth mode at that energy in the range\n";
      }
    }
  }
  report::DrawResponseCharts(dir, rows, model.dofs(), backbone, frequency_grid, base.periods, std::cout);
  if (a.validate == 0) return 0;
  std::vector<ForcedOrbit> orbits;
  for (const report::ResponseRow& r : rows) orbits.push_back(r.orbit);
  const std::vector<ForcedOrbitValidation> results =
      ValidateForcedOrbits(model, orbits, vopt, ProgressBar("validating " + std::to_string(orbits.size()) + " orbits"),
                           vnames);
  std::vector<report::ForcedValidationRow> vrows;
  long failures = 0, consistent = 0;
  const std::size_t per = vopt.integrators.size();
  for (std::size_t i = 0; i < results.size(); ++i) {
    vrows.push_back({rows[i / per].branch, results[i]});
    consistent += results[i].consistent ? 1 : 0;
    if (!results[i].consistent) {
      std::cout << "  inconsistent: w = " << FormatValue(results[i].orbit.frequency) << " ("
                << ToString(results[i].integrator) << "): " << results[i].reason << "\n";
      if (results[i].integrator == Integrator::kExact && results[i].orbit.admissible) ++failures;
    }
  }
  report::ResultFile val(dir, "response_validation.csv");
  report::WriteCsv(val.stream(), report::ForcedValidationColumns(), vrows);
  val.Commit();
  std::cout << "validated " << orbits.size() << " orbits over " << a.validate << " periods: " << consistent << "/"
            << results.size() << " runs consistent; wrote " << a.out << "/response_validation.csv\n";
  if (failures > 0) {
    std::cerr << "error: " << failures << " admissible orbit(s) failed to validate with the exact integrator\n";
    return 4;
  }
  return 0;
}

}  // namespace nsmodal::cli
