#include "nsmodal/validate_settings.h"

#include <string>

#include "nsmodal/error.h"
#include "nsmodal/simulate_settings.h"

namespace nsmodal {

const SettingTable<ValidationRequest>& ValidateSettings() {
  using R = ValidationRequest;
  static const SettingTable<R> table = [] {
    const std::vector<std::string> validate{"validate"};
    std::vector<Setting<R>> settings;
    settings.push_back(TextSetting<R>(
        {"period", {}, "period", "--period", "period", "s", "Period grid FROM:TO:STEP of the orbits (required)", validate},
        &R::period));
    settings.push_back({{"impacts", SettingKind::kIntegerList, "impacts", "--impacts", "impacts", "",
                         "Impacts per period: 1, 2 or both", validate},
                        [](const R& r) -> SettingValue { return r.impacts; },
                        [](R& r, const SettingValue& v, const std::string& field) {
                          r.impacts.clear();
                          if (const auto* reals = std::get_if<std::vector<double>>(&v)) {
                            for (double x : *reals) r.impacts.push_back(WholeNumberOf(x, -1000000, 1000000, field));  // 1 or 2: PlanValidation
                          } else {
                            r.impacts = IntegerListOf(v);
                          }
                        }});
    settings.push_back(TextSetting<R>(
        {"sequence", {}, "sequence", "--sequence", "sequence", "",
         "With several contacts, the contact of each impact, e.g. 1,2 (1 or 2 impacts; replaces impacts)", validate},
        &R::sequence));
    // Lifted twice: ValidationRequest::options, then ValidateOptions::simulate.
    std::vector<Setting<ValidateOptions>> own;
    own.push_back(IntegerSetting<ValidateOptions>(
        {"periods", {}, "periods", "--periods", "periods", "", "Periods simulated per orbit", validate},
        &ValidateOptions::periods));
    own.push_back({{"integrators", SettingKind::kTextList, "integrators", "--integrators", "integrators", "",
                    "Integrators that simulate each orbit: exact, cvode, moreau-jean", validate},
                   [](const ValidateOptions& o) -> SettingValue {
                     std::vector<std::string> names;
                     for (Integrator i : o.integrators) names.push_back(ToString(i));
                     return names;
                   },
                   [](ValidateOptions& o, const SettingValue& v, const std::string& field) {
                     o.integrators.clear();
                     for (const std::string& name : TextListOf(v)) o.integrators.push_back(ParseIntegrator(name, field));
                   }});
    for (Setting<ValidateOptions>& s : LiftSettings(IntegratorSettings().settings(), &ValidateOptions::simulate,
                                                    [](const SettingInfo& info) { return info.Takes("validate"); })) {
      s.info.commands = validate;
      own.push_back(std::move(s));
    }
    // Threads are the machine's, not the scene's: no scene key.
    own.push_back(IntegerSetting<ValidateOptions>(
        {"threads", {}, "", "--threads", "threads", "", "Worker threads (0: all cores)", validate},
        &ValidateOptions::threads));
    for (Setting<R>& s : LiftSettings(own, &R::options, [](const SettingInfo&) { return true; })) {
      settings.push_back(std::move(s));
    }
    return SettingTable<R>("validate", std::move(settings));
  }();
  return table;
}

ValidationPlan PlanValidation(const AnalysisBasis& basis, const Configured<ValidationRequest>& request) {
  const ValidationRequest& r = request.options;
  const FieldNames& names = request.names;
  if (r.period.empty()) {
    throw InputError(names("period"), "is missing: give it with --period, validate.period or period=");
  }
  ValidationPlan plan{r.options, PeriodGrid::Parse(r.period, names("period")), {}, {}};
  if (!r.sequence.empty()) {
    plan.sequence = ParseSequence(r.sequence, static_cast<int>(basis.contacts.size()), names("sequence"));
    const auto impacts = request.origin.find("impacts");
    if (impacts != request.origin.end() && impacts->second.source != SettingSource::kDefault &&
        r.impacts != std::vector<long>{static_cast<long>(plan.sequence.size())}) {
      throw InputError(names("impacts"), "disagrees with " + names("sequence") + " " + r.sequence + ": give one of them");
    }
    plan.impacts = {static_cast<int>(plan.sequence.size())};
  } else {
    if (r.impacts.empty()) throw InputError(names("impacts"), "must name 1, 2 or both");
    for (long m : r.impacts) {
      if (m != 1 && m != 2) throw InputError(names("impacts"), "takes 1 and/or 2, got " + std::to_string(m));
      plan.impacts.push_back(static_cast<int>(m));
    }
  }
  plan.options.Validate(names);
  CheckSweepWork(basis, plan.grid, plan.impacts, names("period"));
  return plan;
}

GridValidation RunValidation(const Model& model, const AnalysisBasis& basis, const ValidationPlan& plan,
                             const std::function<void(long, long)>& progress, const FieldNames& names) {
  SweepOptions sweep;
  sweep.stability = StabilityPolicy::kNone;
  sweep.threads = plan.options.threads;
  sweep.sequence = plan.sequence;
  GridValidation v;
  v.orbits = PotentialOrbits(basis, plan.grid, plan.impacts, sweep);
  v.results = ValidateOrbits(model, v.orbits, plan.options, progress, names);
  v.report = SummarizeValidation(v.results, plan.options, static_cast<long>(v.orbits.size()));
  return v;
}

}  // namespace nsmodal
