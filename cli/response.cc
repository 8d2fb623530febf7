// nsmodal response: frequency- (or amplitude-) response curves of the
// forced, damped system, beside the nonsmooth modes of its conservative twin.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>

#include "commands.h"
#include "common.h"
#include "nsmodal/console.h"
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
  const FieldNames vnames = FieldNames().Set("periods", "--validate").Set("integrators", "--integrators");
  const ValidateOptions vopt = ResponseValidateOptions(a.validate, a.integrators, a.threads, vnames);
  const report::OutputDir dir = report::OutputDir::Prepare(
      a.out, {"response.csv", "response_points.csv", "backbone.csv", "response_validation.csv", "response_energy*",
              "response_max_xc*"});
  const ResponseLevels r = ComputeResponseLevels(
      model, base, levels,
      [frequency_grid](double level) {
        return ProgressBar("response " + std::string(frequency_grid ? "a = " : "w = ") + FormatValue(level));
      },
      [](const ResponseCurve& curve, int first_branch) { report::PrintResponseCurve(std::cout, curve, first_branch); });
  report::ResultFile out(dir, "response.csv");
  report::WriteCsv(out.stream(), report::ResponseColumns(model.dofs()), r.rows);
  out.Commit();
  report::ResultFile pts(dir, "response_points.csv");
  report::WriteCsv(pts.stream(), report::ResponsePointColumns(), r.points);
  pts.Commit();
  std::cout << "wrote " << r.rows.size() << " points on " << r.branches << " branches to " << a.out
            << "/response.csv, " << r.points.size() << " special points to " << a.out << "/response_points.csv\n";
  if (frequency_grid) {
    // The nonsmooth mode of the conservative twin over the same frequencies.
    const BackboneMatch match = MatchBackbone(model, base, r.points, ProgressBar("backbone"));
    report::ResultFile bb(dir, "backbone.csv");
    std::vector<OrbitRecord> records;
    for (const auto& list : match.backbone.at) records.insert(records.end(), list.begin(), list.end());
    report::WriteCsv(bb.stream(), report::BackboneColumns(), records);
    bb.Commit();
    report::PrintResponsePeaks(std::cout, r.points, match, base.periods);
  }
  report::DrawResponseCharts(dir, r.rows, model.dofs(), frequency_grid, frequency_grid, base.periods, std::cout);
  if (a.validate == 0) return 0;
  const ResponseValidation v = ValidateResponse(
      model, r.rows, vopt, ProgressBar("validating " + std::to_string(r.rows.size()) + " orbits"), vnames);
  report::PrintInconsistent(std::cout, v);
  report::ResultFile val(dir, "response_validation.csv");
  report::WriteCsv(val.stream(), report::ForcedValidationColumns(), v.rows);
  val.Commit();
  std::cout << "validated " << r.rows.size() << " orbits over " << a.validate << " periods: " << v.consistent << "/"
            << v.rows.size() << " runs consistent; wrote " << a.out << "/response_validation.csv\n";
  if (v.failures > 0) {
    std::cerr << "error: " << v.failures << " admissible orbit(s) failed to validate with the exact integrator\n";
    return 4;
  }
  return 0;
}

}  // namespace nsmodal::cli
