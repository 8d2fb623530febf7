// nsmodal response: frequency- (or amplitude-) response curves of the
// forced, damped system, beside the nonsmooth modes of its conservative twin.
#include <iostream>
#include <optional>
#include <string>

#include "commands.h"
#include "nsmodal/console.h"
#include "nsmodal/error.h"
#include "nsmodal/figures.h"
#include "nsmodal/output.h"
#include "nsmodal/response.h"
#include "nsmodal/scene.h"
#include "nsmodal/tables.h"
#include "nsmodal/validate.h"

namespace nsmodal::cli {

using report::ProgressBar;

int RunResponse(const ResponseArgs& a) {
  const Scene scene = LoadScene(a.scene);
  const Model& model = scene.model;
  auto is_grid = [](const std::optional<std::string>& text) { return text && text->find(':') != std::string::npos; };
  const bool frequency_grid = is_grid(a.frequency), amplitude_grid = is_grid(a.amplitude);
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
  report::WriteCsvFile(dir, "response.csv", report::ResponseColumns(model.dofs()), r.rows);
  report::WriteCsvFile(dir, "response_points.csv", report::ResponsePointColumns(), r.points);
  std::cout << "wrote " << r.rows.size() << " points on " << r.branches << " branches to " << a.out
            << "/response.csv, " << r.points.size() << " special points to " << a.out << "/response_points.csv\n";
  if (frequency_grid) {
    // The nonsmooth mode of the conservative twin over the same frequencies.
    const BackboneMatch match = MatchBackbone(model, base, r.points, ProgressBar("backbone"));
    std::vector<OrbitRecord> records;
    for (const auto& list : match.backbone.at) records.insert(records.end(), list.begin(), list.end());
    report::WriteCsvFile(dir, "backbone.csv", report::BackboneColumns(), records);
    report::PrintResponsePeaks(std::cout, r.points, match, base.periods);
  }
  report::DrawResponseCharts(dir, r.rows, model.dofs(), frequency_grid, frequency_grid, base.periods, std::cout);
  if (a.validate == 0) return 0;
  const ResponseValidation v = ValidateResponse(
      model, r.rows, vopt, ProgressBar("validating " + std::to_string(r.rows.size()) + " orbits"), vnames);
  report::PrintInconsistent(std::cout, v);
  report::WriteCsvFile(dir, "response_validation.csv", report::ForcedValidationColumns(), v.rows);
  std::cout << "validated " << r.rows.size() << " orbits over " << a.validate << " periods: " << v.consistent << "/"
            << v.rows.size() << " runs consistent; wrote " << a.out << "/response_validation.csv\n";
  if (v.failures > 0) {
    std::cerr << "error: " << v.failures << " admissible orbit(s) failed to validate with the exact integrator\n";
    return 4;
  }
  return 0;
}

}  // namespace nsmodal::cli
