#include "command_line.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <string>
#include <utility>

#include "nsmodal/atlas.h"
#include "nsmodal/curve.h"
#include "nsmodal/console.h"
#include "nsmodal/error.h"
#include "nsmodal/explore.h"
#include "nsmodal/family_parameter.h"
#include "nsmodal/figure_subjects.h"
#include "nsmodal/figures.h"
#include "nsmodal/json.h"
#include "nsmodal/output.h"
#include "nsmodal/response.h"
#include "nsmodal/scene.h"
#include "nsmodal/simulate_settings.h"
#include "nsmodal/tables.h"
#include "nsmodal/transitions.h"
#include "nsmodal/truncation.h"
#include "nsmodal/validate.h"
#include "nsmodal/validate_settings.h"
#include "nsmodal/work_precision.h"

namespace nsmodal::cli {

using report::ProgressBar;
namespace {

void CheckImpacts(int impacts) {
  if (impacts != 1 && impacts != 2) {
    throw InputError("--impacts", "orbits and orbit compute 1 or 2 impacts per period, got " +
                                      std::to_string(impacts) + " (use 'nsmodal explore' for 3 or more)");
  }
}

}  // namespace

int RunOrbits(const OrbitsArgs& a) {
  if (!a.sequence) CheckImpacts(a.impacts);  // before the scene is read
  const PeriodGrid grid = PeriodGrid::Parse(a.period);
  const Scene scene = LoadScene(a.scene);
  // --modes K: the sweep on the first K modes; orbits.csv in the N dofs, with the bound's column.
  std::optional<ModalTruncation> truncation;
  if (a.modes) truncation = TruncateModesAsGiven(scene.model, *a.modes, "--modes");
  if (truncation) report::PrintSweepTruncation(std::cout, *truncation);
  const AnalysisBasis b(truncation ? truncation->model : scene.model);
  const auto [impacts, sequence] =
      ImpactSequence(a.impacts, a.sequence, static_cast<int>(b.contacts.size()), FieldNames("--"));
  CheckSweepWork(b, grid, {impacts}, "--period", impacts == 1);
  const report::TableFormat format = report::ParseTableFormat(a.format);
  const report::OutputDir dir = report::OutputDir::Prepare(a.out, report::TableFileNames({"orbits", "transitions"}));
  SweepOptions opt;  // stability: potential
  opt.threads = a.threads;
  opt.sequence = sequence;
  opt.progress = ProgressBar(impacts == 1 ? "1-ipp orbits" : "2-ipp orbits");
  const report::SweepWritten written =
      report::WriteSweepTable(dir, "orbits", b, grid, impacts, opt, truncation ? &*truncation : nullptr, format);
  std::cout << "wrote " << written.orbits << " orbits (" << written.admissible << " admissible) to " << a.out << "/"
            << report::TableFileName("orbits", format) << "\n";
  if (impacts == 1) {
    // Zone boundaries and the stability changes inside the zones (issue 13).
    const std::vector<Transition> transitions = written.zones.Transitions(b);
    std::cout << "wrote " << transitions.size() << " transitions to " << a.out << "/"
              << report::WriteTableFile(dir, "transitions", report::TransitionColumns(), transitions, format) << "\n";
  }
  return 0;
}

int RunBench(const BenchArgs& a) {
  CheckBenchModel(LoadScene(a.scene).model);
  const report::OutputDir dir =
      report::OutputDir::Prepare(a.out, {"work_precision.csv", "grazing.csv", "work_precision_*"});
  const WorkPrecisionOptions opt{
      .quick = a.quick, .progress = ProgressBar(a.quick ? "work-precision (quick)" : "work-precision")};
  const std::vector<WorkPrecisionRow> rows = RunWorkPrecision(opt);
  report::WriteCsvFile(dir, "work_precision.csv", report::WorkPrecisionColumns(), rows);
  const std::vector<GrazingRow> grazing = RunGrazingFailures(opt);
  report::WriteCsvFile(dir, "grazing.csv", report::GrazingColumns(), grazing);
  const int failed_charts = report::DrawWorkPrecisionCharts(dir, rows, std::cerr);
  report::PrintBenchTables(std::cout, rows, grazing);
  std::cout.flush();
  std::cerr << "wrote " << rows.size() << " work-precision rows and " << grazing.size() << " grazing rows to " << a.out
            << " (work_precision.csv, grazing.csv, work_precision_*.png/svg)\n";
  if (failed_charts) throw report::OutputError(std::to_string(failed_charts) + " chart(s) could not be drawn");
  return 0;
}

int RunValidate(const ValidateArgs& a) {
  const Scene scene = LoadScene(a.scene);
  const AnalysisBasis b(scene.model);
  const Configured<ValidationRequest> request = ValidateSettings().Resolve({&scene.validate, &a.flags});
  const ValidationPlan plan = PlanValidation(b, request);
  const ValidateOptions& opt = plan.options;
  const report::TableFormat format = report::ParseTableFormat(a.format);
  std::vector<std::string> owned = report::TableFileNames({"validation"});
  owned.push_back("summary.json");
  const report::OutputDir dir = report::OutputDir::Prepare(a.out, owned);
  const GridValidation v = RunValidation(scene.model, b, plan, ProgressBar("validate"), request.names);
  const ValidationReport& report = v.report;
  const std::string table = report::WriteTableFile(dir, "validation", report::ValidationColumns(), v.results, format);
  report::WriteResult(dir, "summary.json", report::ValidationJson(report, v.results, request).dump(2) + "\n");
  if (report.stable_perturbed + report.unstable_rated > 0) {
    std::cout << "perturbed by " << opt.perturbation << " |y| in the nontrivial Floquet subspace (exact): "
              << report.stable_perturbed << " stable orbits grew at most x" << report.stable_worst_amplification
              << " over " << opt.periods << " periods; " << report.unstable_within_tolerance << "/"
              << report.unstable_rated << " unstable orbits grew within "
              << 100.0 * ValidationReport::kRateTolerance << " % of log|lambda| (worst "
              << 100.0 * report.unstable_worst_rate_error << " %)\n";
  }
  std::cout << "validated " << v.orbits.size() << " orbits over " << opt.periods << " periods:";
  for (const auto& [integrator, t] : report.integrators) {
    std::cout << "  " << ToString(integrator) << " " << t.consistent << "/" << t.checked << " consistent";
  }
  std::cout << "\nwrote " << a.out << "/" << table << " and " << a.out << "/summary.json\n";
  for (std::size_t i : report.inconsistent) {
    const OrbitValidation& r = v.results[i];
    std::cout << "  inconsistent: T = " << r.orbit.period
              << (r.orbit.times.empty() ? "" : " t2 = " + FormatValue(r.orbit.times[0])) << " ("
              << ToString(r.integrator) << "): " << r.reason << "\n";
  }
  if (!report.passed()) {
    std::cerr << "error: " << report.admissible_exact_failures.size()
              << " admissible orbit(s) failed to validate with the exact integrator (see above)\n";
    return 4;
  }
  return 0;
}

int RunSimulate(const SimulateArgs& a) {
  const Scene scene = LoadScene(a.scene);
  const Model& m = scene.model;
  const Configured<SimulationRequest> request = SimulateSettings().Resolve({&scene.simulate, &a.flags});
  const SimulateOptions& opt = request.options.options;
  const SimulationPlan plan = PlanSimulation(m, request);
  report::PrintSimulationTruncation(std::cout, plan, m.FirstContact());
  const report::TableFormat format = report::ParseTableFormat(a.format);
  std::vector<std::string> owned = report::TableFileNames({"trajectory", "impacts"});
  owned.push_back("summary.json");
  const report::OutputDir dir = report::OutputDir::Prepare(a.out, owned);
  report::TableWriter<report::Sample> traj(dir, "trajectory", report::TrajectoryColumns(m.dofs()), format);
  report::TableWriter<ContactEvent> imp(dir, "impacts", report::ImpactColumns(m.dofs()), format);
  SimulationObserver obs;
  obs.on_sample = [&](double t, const Eigen::VectorXd& z) { traj.Append(report::SampleOf(m, t, z)); };
  obs.on_impact = [&](const ContactEvent& ev) { imp.Append(ev); };
  const auto bar = ProgressBar("simulate");
  if (bar) {
    obs.on_progress = [&](double t) { bar(static_cast<long>(1000.0 * t / opt.t_end), 1000); };
  }
  const SimulationSummary s = RunSimulation(m, plan, opt, obs);
  if (bar) bar(1000, 1000);
  traj.Commit();
  imp.Commit();
  nlohmann::json summary = report::SimulationJson(s, request);
  if (plan.truncation) summary["truncation"] = report::TruncationJson(*plan.truncation, plan.initial_energy);
  report::WriteResult(dir, "summary.json", summary.dump(2) + "\n");
  std::cout << ToString(opt.integrator) << ": t = " << s.final_time << ", " << s.impacts << " impacts, " << s.grazes
            << " grazes, " << s.zeno_events << " Zeno sequences, sticking " << s.sticking_time << ", energy drift "
            << s.energy_drift << ", " << s.wall_time_s << " s; wrote " << a.out << "/{" << traj.file_name() << ","
            << imp.file_name() << ",summary.json}\n";
  if (s.status != SimulationStatus::kFinished) {
    std::cerr << "error: simulation stopped: " << s.message << "\n";
    return 3;
  }
  return 0;
}

int RunSettings(const SettingsArgs& a) {
  if (a.json) {
    std::cout << report::SettingsReferenceJson().dump(2) << "\n";
  } else {
    report::PrintSettingsReference(std::cout);
  }
  return 0;
}

int RunOrbit(const OrbitArgs& a) {
  if (!a.sequence) CheckImpacts(a.impacts);
  if (!(a.period > 0.0) || !std::isfinite(a.period)) {
    throw InputError("--period", "must be positive, got " + FormatValue(a.period));
  }
  const AnalysisBasis b(LoadScene(a.scene).model);
  const auto [impacts, sequence] =
      ImpactSequence(a.impacts, a.sequence, static_cast<int>(b.contacts.size()), FieldNames("--"));
  SweepOptions opt;  // stability: potential
  opt.sequence = sequence;
  const std::vector<OrbitRecord> orbits = OrbitsAt(b, a.period, impacts, opt, "--period");
  if (a.json) {
    std::cout << report::OrbitsJson(orbits).dump(2) << "\n";
  } else {
    report::PrintOrbits(std::cout, orbits, impacts, a.period);
  }
  return 0;
}

int RunExplore(const ExploreArgs& a) {
  if (a.grid < 4 || a.grid > 200) throw InputError("--grid", "must lie in [4, 200], got " + std::to_string(a.grid));
  const PeriodGrid range = PeriodGrid::Parse(a.period);
  const AnalysisBasis b(LoadScene(a.scene).model);
  std::vector<int> sequence;
  int impacts = a.impacts;
  if (a.sequence) {
    sequence = ParseSequence(*a.sequence, static_cast<int>(b.contacts.size()), "--sequence", 6);
    impacts = static_cast<int>(sequence.size());  // (an --impacts given agrees: command_line.cc)
  }
  if (impacts < 3 || impacts > 6) {
    throw InputError(a.sequence ? "--sequence" : "--impacts",
                     "explore takes 3 to 6 impacts per period, got " + std::to_string(impacts) +
                         " (use 'nsmodal orbits' for 1 or 2)");
  }
  std::optional<PeriodGrid> follow;
  if (a.follow) follow = PeriodGrid::Parse(*a.follow, "--follow");
  if (follow) CheckFamilyRange(b, impacts, follow->from, follow->to, FieldNames("--"));
  const ExploreReport r = ExploreImpacts(
      b, range.Values(), {.impacts = impacts, .sequence = sequence, .grid = a.grid, .progress = ProgressBar("explore")});
  if (a.json) {
    std::cout << report::ExploreJson(r).dump(2) << "\n";
    return 0;
  }
  report::PrintExplore(std::cout, r, range.Count());
  if (follow) {
    const auto families = FollowNewFamilies(b, r, follow->from, follow->to, {.step = follow->step});
    report::PrintFamilies(std::cout, families, follow->step);
  }
  return 0;
}

int RunFigures(const FiguresArgs& a) {
  const Scene scene = LoadScene(a.scene);
  if (scene.bar) {
    // A bar: its contact in space and time (the paper's figures are of a
    // system of a few masses).
    if (a.period) throw InputError("--period", "the figures of a bar ([system] bar) take no period grid");
    const report::OutputDir dir = report::OutputDir::Prepare(a.out, {"bar_spacetime*"});
    const report::FiguresResult r = report::DrawBarFigures(scene.model, *scene.bar, dir, std::cout);
    if (r.failed) throw report::OutputError("bar_spacetime could not be drawn (see above)");
    return 0;
  }
  // A free mass between walls has no 1-impact family for Figs. 2-17: Fig. 18 alone.
  const bool rigid = RigidBodyModes(scene.model.stiffness) > 0;
  // The paper's figures draw x_c of one dof against the wall x_c = d above it.
  const Contact& first = scene.model.FirstContact();
  if (!rigid && (first.form != Contact::Form::kDof || !first.upper)) {
    throw InputError("contact", "figures draw contact 1 as the paper's stop x_c <= d on one dof; contact 1 here is " +
                                    first.Describe() + ": write that wall first, or as an upper dof stop");
  }
  const AnalysisBasis b(scene.model);
  const PeriodGrid grid = FiguresGrid(b, a.period, "--period");
  const report::OutputDir dir = report::OutputDir::Prepare(
      a.out, {"fig[01][0-9]_*", "multipliers_one_impact*", "time_history*", "validation_orbits*", "validation_deviation*",
              "fep_all_families*"});
  report::FiguresResult r;
  if (rigid) {
    std::cout << "the model has a rigid-body mode: no 1-impact families, so the paper's Figs. 2-17 are not drawn; "
                 "Fig. 18, the sequences of two contacts\n";
    r = report::DrawSequenceFigures(b, grid.Values(), dir, std::cout);
  } else {
    AtlasOptions opt;
    opt.sweep.threads = a.threads;
    opt.sweep.progress = ProgressBar("1- and 2-ipp sweep");
    const Atlas atlas = ComputeAtlas(b, grid, opt);
    report::PrintAtlas(std::cout, atlas);
    r = report::DrawPaperFigures(scene.model, b, first.dof, atlas, dir, std::cout);
  }
  if (r.failed) throw report::OutputError(std::to_string(r.failed) + " figure(s) could not be drawn (see above)");
  return 0;
}

int RunResponse(const ResponseArgs& a) {
  const Model model = LoadScene(a.scene).model;
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
  // The grid's flag, then the held parameter's values (none: the scene's).
  const PeriodGrid grid = PeriodGrid::Parse(frequency_grid ? *a.frequency : *a.amplitude,
                                            frequency_grid ? "--frequency" : "--amplitude");
  const std::optional<std::string>& held = frequency_grid ? a.amplitude : a.frequency;
  const ResponseRequest request = MakeResponseRequest(
      model, frequency_grid ? ResponseParameter::kFrequency : ResponseParameter::kAmplitude, grid,
      held ? ParseValues(*held, frequency_grid ? "--amplitude" : "--frequency") : std::vector<double>{}, a.impacts,
      a.periods, FieldNames("--"), a.sequence);
  // --validate's options checked now, before any work or file.
  const FieldNames vnames = FieldNames().Set("periods", "--validate").Set("integrators", "--integrators");
  const ValidateOptions vopt = ResponseValidateOptions(a.validate, a.integrators, a.threads, vnames);
  const report::OutputDir dir = report::OutputDir::Prepare(
      a.out, {"response.csv", "response_points.csv", "backbone.csv", "response_validation.csv", "response_energy*",
              "response_amplitude*", "response_max_xc*"});
  const ResponseLevels r = ComputeResponseLevels(
      model, request.options, request.levels,
      [frequency_grid](double level) {
        return ProgressBar("response " + std::string(frequency_grid ? "a = " : "w = ") + FormatValue(level));
      },
      [](const ResponseCurve& curve, int first_branch) { report::PrintResponseCurve(std::cout, curve, first_branch); });
  report::WriteCsvFile(dir, "response.csv", report::ResponseColumns(model.dofs()), r.rows);
  report::WriteCsvFile(dir, "response_points.csv", report::ResponsePointColumns(), r.points);
  std::cout << "wrote " << r.rows.size() << " points on " << r.branches << " branches to " << a.out
            << "/response.csv, " << r.points.size() << " special points to " << a.out << "/response_points.csv\n";
  const std::optional<std::string> no_backbone = NoBackbone(model, request.options);
  if (frequency_grid && no_backbone) std::cout << "no backbone: " << *no_backbone << "\n";
  std::vector<OrbitRecord> records;  // the backbone's
  if (frequency_grid && !no_backbone) {
    const BackboneMatch match = MatchBackbone(model, request.options, r.points, ProgressBar("backbone"));
    for (const auto& list : match.backbone.at) records.insert(records.end(), list.begin(), list.end());
    report::WriteCsvFile(dir, "backbone.csv", report::BackboneColumns(MakeModalBasis(model)), records);
    report::PrintResponsePeaks(std::cout, r.points, match, a.periods);
  }
  report::DrawResponseCharts(dir, r.rows, r.points, model.dofs(), frequency_grid && !no_backbone ? &records : nullptr,
                             frequency_grid, a.periods, std::cout);
  if (a.validate == 0) return 0;
  const ResponseValidation v = ValidateResponse(
      model, r.rows, vopt, ProgressBar("validating " + std::to_string(r.rows.size()) + " orbits"), vnames);
  report::PrintInconsistent(std::cout, v);
  report::WriteCsvFile(dir, "response_validation.csv", report::ForcedValidationColumns(), v.rows);
  report::PrintResponseValidation(std::cout, v, r.rows.size(), a.validate, a.out + "/response_validation.csv");
  if (v.failures > 0) {
    std::cerr << "error: " << v.failures << " admissible orbit(s) failed to validate with the exact integrator\n";
    return 4;
  }
  return 0;
}

namespace {

// continue --second: the curves of the --follow points in both parameters.
int RunCurves(const ContinueArgs& a, const Model& model) {
  if (!a.second_range) throw InputError("--second-range", "is needed with --second");
  if (!a.follow) throw InputError("--follow", "is needed with --second (fold, period-doubling or grazing)");
  CurveOptions o = MakeCurveRequest(model, a.parameter, a.range, *a.second, *a.second_range, *a.follow, a.impacts,
                                    a.periods, FieldNames("--").Set("second_range", "--second-range"), a.sequence);
  const report::OutputDir dir = report::OutputDir::Prepare(a.out, {"curve.csv", "curve.*"});
  o.progress = ProgressBar(*a.follow + " curves in (" + a.parameter + ", " + *a.second + ")");
  const CurveSet set = FollowCurves(model, o);
  for (std::size_t c = 0; c < set.ends.size(); ++c) {
    long points = 0;
    for (const CurvePoint& p : set.rows) points += p.curve == static_cast<int>(c) && p.kind == *a.follow;
    std::cout << "curve " << c + 1 << ": " << points << " points; " << set.ends[c] << "\n";
  }
  for (const CurvePoint& p : set.rows) {
    if (p.kind != *a.follow) {
      std::cout << "curve " << p.curve + 1 << " meets " << p.kind << " at " << a.parameter << " = "
                << FormatValue(p.first) << ", " << *a.second << " = " << FormatValue(p.second) << "\n";
    }
  }
  for (const std::string& n : set.notes) std::cout << "note: " << n << "\n";
  report::WriteCsvFile(dir, "curve.csv", report::CurveColumns(model.dofs(), a.parameter, *a.second), set.rows);
  std::cout << "wrote " << set.rows.size() << " points on " << set.curves << " curves to " << a.out << "/curve.csv\n";
  // Beside curves in the frequency: the backbone's transitions (the
  // conservative twin's 1-impact mode, as `response` draws it), over the
  // periods n 2 pi / w of the window.
  std::vector<Transition> backbone;
  const bool frequency = o.first.kind == ModelParameter::Kind::kFrequency;
  ResponseOptions as_response;
  as_response.sequence = o.sequence;
  const bool first_contact = std::all_of(o.sequence.begin(), o.sequence.end(), [](int j) { return j == 0; });
  if (frequency && first_contact && !NoBackbone(model, as_response)) {
    const double t_lo = o.periods * 2.0 * M_PI / o.first_range.to, t_hi = o.periods * 2.0 * M_PI / o.first_range.from;
    backbone = OneImpactTransitions(AnalysisBasis(ConservativeTwin(model)), t_lo, t_hi, (t_hi - t_lo) / 2000.0);
  }
  report::DrawCurveChart(dir, set.rows, model.dofs(), *a.follow, a.parameter, *a.second, frequency ? &backbone : nullptr,
                         o.periods, std::cout);
  return 0;
}

}  // namespace

// continue on a scene with no force: the free family's transitions.
int RunFamily(const ContinueArgs& a, const Model& model) {
  if (a.second) throw InputError("--second", "needs a forced scene (a [forcing] table): curves follow forced responses");
  // (What follows a forced response only: refused, not ignored.)
  for (const auto& [given, flag] : {std::pair{a.second_range.has_value(), "--second-range"},
                                    std::pair{a.follow.has_value(), "--follow"},
                                    std::pair{a.sequence.has_value(), "--sequence"}, std::pair{a.impacts != 1, "--impacts"},
                                    std::pair{a.periods != 1, "--periods"}}) {
    if (given) {
      throw InputError(flag, "is for a forced scene; a scene with no [forcing] table follows its free 1-impact "
                             "family (--period)");
    }
  }
  if (!a.period) {
    throw InputError("--period", "is needed for a scene with no [forcing] table: the free 1-impact family's period "
                                 "grid FROM:TO:STEP, whose transitions are followed (or add a [forcing] table to "
                                 "follow a forced response)");
  }
  const ModelParameter p = ParseModelParameter(model, a.parameter, "--parameter");
  const PeriodGrid values = ParseParameterRange(a.range, "--range");
  const PeriodGrid periods = PeriodGrid::Parse(*a.period, "--period");
  CheckFamilyRequest(model, p, values, periods, "--parameter", "--range", "--period");
  const report::OutputDir dir = report::OutputDir::Prepare(a.out, {"transitions.csv"});
  const FamilyContinuation f =
      FollowFamily(model, p, values, periods, ProgressBar("1-ipp transitions in " + a.parameter), "--parameter",
                   "--range", "--period");
  for (const std::string& n : f.notes) std::cout << "note: " << n << "\n";
  report::WriteCsvFile(dir, "transitions.csv", report::FamilyColumns(a.parameter), f.rows);
  std::cout << "wrote " << f.rows.size() << " transitions on " << f.tracks << " tracks to " << a.out
            << "/transitions.csv\n";
  return 0;
}

int RunContinue(const ContinueArgs& a) {
  const Model model = LoadScene(a.scene).model;
  if (!model.forcing.HasHarmonic()) return RunFamily(a, model);
  if (a.period) throw InputError("--period", "is for a scene with no [forcing] table (the free family's periods)");
  if (a.second) return RunCurves(a, model);
  for (const auto& [given, flag] : {std::pair{a.second_range.has_value(), "--second-range"},
                                    std::pair{a.follow.has_value(), "--follow"}}) {
    if (given) throw InputError(flag, "is given without --second (the second parameter of a curve)");
  }
  const ResponseRequest request =
      MakeContinuationRequest(model, a.parameter, a.range, a.impacts, a.periods, FieldNames("--"), a.sequence);
  const report::OutputDir dir = report::OutputDir::Prepare(a.out, {"continuation.csv", "continuation_points.csv"});
  const ResponseLevels r = ComputeResponseLevels(
      model, request.options, request.levels,
      [&a](double) { return ProgressBar("continuation in " + a.parameter); },
      [](const ResponseCurve& curve, int first_branch) { report::PrintResponseCurve(std::cout, curve, first_branch); });
  report::WriteCsvFile(dir, "continuation.csv", report::ContinuationColumns(model.dofs(), a.parameter), r.rows);
  report::WriteCsvFile(dir, "continuation_points.csv", report::ContinuationPointColumns(a.parameter), r.points);
  std::cout << "wrote " << r.rows.size() << " points on " << r.branches << " branches to " << a.out
            << "/continuation.csv, " << r.points.size() << " special points to " << a.out
            << "/continuation_points.csv\n";
  return 0;
}

}  // namespace nsmodal::cli
