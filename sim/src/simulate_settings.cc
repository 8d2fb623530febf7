#include "nsmodal/simulate_settings.h"

#include <cmath>
#include <functional>
#include <string>

#include "nsmodal/error.h"

namespace nsmodal {
namespace {

// A setting whose default is "not given" (std::nullopt: no value), of a
// kind whose values `read` converts (naming the field on a bad one).
template <class Options, class T>
Setting<Options> OptionalSetting(SettingInfo info, SettingKind kind, std::optional<T> Options::*member,
                                 T (*read)(const SettingValue&, const std::string&)) {
  info.kind = kind;
  return {std::move(info),
          [member](const Options& o) -> SettingValue {
            if (const auto& v = o.*member) return *v;
            return std::monostate{};
          },
          [member, read](Options& o, const SettingValue& v, const std::string& field) { o.*member = read(v, field); }};
}

double ReadReal(const SettingValue& v, const std::string&) { return RealOf(v); }
long ReadModes(const SettingValue& v, const std::string& field) { return WholeNumberOf(v, -kMaxDofs, kMaxDofs, field); }

// The ranges of the integrator's settings (SimulateOptions::Validate runs
// them, then the checks that relate two settings).
void Positive(const SettingValue& v, const std::string& field) {
  const double x = RealOf(v);
  if (!(x > 0.0) || !std::isfinite(x)) throw InputError(field, "must be positive and finite, got " + FormatValue(x));
}

template <class Options>
Setting<Options> Checked(Setting<Options> s, std::function<void(const SettingValue&, const std::string&)> check) {
  s.check = std::move(check);
  return s;
}

const std::vector<std::string> kSimulate{"simulate"};
const std::vector<std::string> kSimulateAndValidate{"simulate", "validate"};

}  // namespace

const SettingTable<SimulateOptions>& IntegratorSettings() {
  using O = SimulateOptions;
  static const SettingTable<O> table(
      "simulate",
      {
          {{"integrator", SettingKind::kText, "integrator", "--integrator", "integrator", "",
            "exact (closed-form flight, guaranteed impact search), cvode (SUNDIALS CVODE with root finding) or "
            "moreau-jean (event-capturing time-stepping)",
            kSimulate},
           [](const O& o) -> SettingValue { return ToString(o.integrator); },
           [](O& o, const SettingValue& v, const std::string& field) { o.integrator = ParseIntegrator(TextOf(v), field); }},
          Checked(RealSetting<O>({"t_end", {}, "t_end", "--t-end", "t_end", "s", "Final time of the run", kSimulate}, &O::t_end),
                  Positive),
          Checked(RealSetting<O>({"rtol", {}, "rtol", "--rtol", "rtol", "",
                          "CVODE's relative tolerance (at least 1e-15)", kSimulateAndValidate},
                         &O::rtol),
                  [](const SettingValue& v, const std::string& field) {
                    Positive(v, field);
                    if (RealOf(v) < 1e-15) {
                      throw InputError(field, "below 1e-15 is beyond double precision, got " + FormatValue(RealOf(v)));
                    }
                  }),
          Checked(RealSetting<O>({"atol", {}, "atol", "--atol", "atol", "", "CVODE's absolute tolerance", kSimulateAndValidate},
                         &O::atol),
                  Positive),
          Checked(TextSetting<O>({"method", {}, "method", "--method", "method", "", "CVODE's method: adams or bdf", kSimulate},
                         &O::cvode_method),
                  [](const SettingValue& v, const std::string& field) {
                    if (TextOf(v) != "bdf" && TextOf(v) != "adams") {
                      throw InputError(field, "must be bdf or adams, got '" + TextOf(v) + "'");
                    }
                  }),
          Checked(RealSetting<O>({"step", {}, "step", "--step", "step", "s", "Moreau-Jean's time step", kSimulateAndValidate},
                         &O::step),
                  Positive),
          Checked(RealSetting<O>({"theta", {}, "theta", "--theta", "theta", "", "Moreau-Jean's theta, in [0.5, 1]", kSimulate},
                         &O::theta),
                  [](const SettingValue& v, const std::string& field) {
                    const double x = RealOf(v);
                    if (!(x >= 0.5 && x <= 1.0)) throw InputError(field, "must lie in [0.5, 1], got " + FormatValue(x));
                  }),
          Checked(RealSetting<O>({"root_tol", {}, "root_tol", "--root-tol", "root_tol", "",
                          "The exact integrator's contact tolerance, relative to max(d, the amplitude of x_c)",
                          kSimulateAndValidate},
                         &O::root_tol),
                  [](const SettingValue& v, const std::string& field) {
                    Positive(v, field);
                    if (RealOf(v) >= 1e-3) throw InputError(field, "must be below 1e-3, got " + FormatValue(RealOf(v)));
                  }),
          Checked(RealSetting<O>({"sample_dt", {}, "sample_dt", "--sample-dt", "sample_dt", "s",
                          "Trajectory sampling interval (0: no trajectory)", kSimulate},
                         &O::sample_dt),
                  [](const SettingValue& v, const std::string& field) {
                    const double x = RealOf(v);
                    if (!(x >= 0.0) || !std::isfinite(x)) {
                      throw InputError(field, "must be >= 0 and finite, got " + FormatValue(x));
                    }
                  }),
      });
  return table;
}

const SettingTable<SimulationRequest>& SimulateSettings() {
  using R = SimulationRequest;
  static const SettingTable<R> table = [] {
    std::vector<Setting<R>> settings = LiftSettings(IntegratorSettings().settings(), &R::options,
                                                    [](const SettingInfo& info) { return info.Takes("simulate"); });
    settings.push_back(RealListSetting<R>({"initial_position", {}, "initial_position", "--x0", "x0", "m",
                                           "Initial position x(0), one value per dof (required)", kSimulate},
                                          &R::initial_position));
    settings.push_back(RealListSetting<R>({"initial_velocity", {}, "initial_velocity", "--v0", "v0", "m/s",
                                           "Initial velocity v(0), one value per dof (default: at rest)", kSimulate},
                                          &R::initial_velocity));
    settings.push_back(OptionalSetting<R, long>(
        {"modes", {}, "modes", "--modes", "modes", "",
         "Simulate on the first K linear modes only (modal truncation; not with contact_tolerance)", kSimulate},
        SettingKind::kInteger, &R::modes, &ReadModes));
    settings.push_back(OptionalSetting<R, double>(
        {"contact_tolerance", {}, "contact_tolerance", "--contact-tolerance", "contact_tolerance", "m",
         "Keep the fewest modes whose neglected share of x_c is at most this at the initial energy (not with modes)",
         kSimulate},
        SettingKind::kReal, &R::contact_tolerance, &ReadReal));
    return SettingTable<R>("simulate", std::move(settings));
  }();
  return table;
}

namespace {

Eigen::VectorXd VectorOf(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

// The precedence of a source: a flag or a keyword over a scene over a default.
int Rank(SettingSource s) {
  switch (s) {
    case SettingSource::kDefault: return 0;
    case SettingSource::kScene: return 1;
    case SettingSource::kFlag:
    case SettingSource::kKeyword: return 2;
  }
  return 0;
}

}  // namespace

SimulationPlan PlanSimulation(const Model& model, const Configured<SimulationRequest>& request) {
  const SimulationRequest& r = request.options;
  const FieldNames& names = request.names;
  r.options.Validate(names);
  Validate(model);
  const int n = model.dofs();
  if (r.initial_position.empty()) {
    throw InputError(names("initial_position"), "is missing: give it in [simulate] (initial_position), with --x0 or x0=");
  }
  SimulationPlan plan;
  plan.x0 = VectorOf(r.initial_position);
  plan.v0 = r.initial_velocity.empty() ? Eigen::VectorXd::Zero(n) : VectorOf(r.initial_velocity);
  auto check_state = [n, &names](const Eigen::VectorXd& v, const char* key) {
    if (v.size() != n) {
      throw InputError(names(key), "must have " + std::to_string(n) + " entries, got " + std::to_string(v.size()));
    }
    if (!v.allFinite()) throw InputError(names(key), "has a non-finite entry");
  };
  check_state(plan.x0, "initial_position");
  check_state(plan.v0, "initial_velocity");
  Eigen::VectorXd z(2 * n);
  z << plan.x0, plan.v0;
  plan.initial_energy = MechanicalEnergy(model, z);

  // One of modes and contact_tolerance: a value given by a later face
  // replaces the other (--contact-tolerance over a scene's modes).
  std::optional<long> modes = r.modes;
  std::optional<double> tolerance = r.contact_tolerance;
  if (modes && tolerance) {
    const int rm = Rank(request.origin.at("modes").source), rt = Rank(request.origin.at("contact_tolerance").source);
    if (rm > rt) tolerance.reset();
    if (rt > rm) modes.reset();
    if (modes && tolerance) {
      throw InputError(names("modes"), "and " + names("contact_tolerance") + " are both given: give one of them");
    }
  }
  if (modes) {
    plan.truncation = TruncateModesAsGiven(model, static_cast<double>(*modes), names("modes"));
  } else if (tolerance) {
    plan.truncation = TruncateForContactBound(model, plan.initial_energy, *tolerance, names("contact_tolerance"));
  }
  return plan;
}

SimulationSummary RunSimulation(const Model& model, const SimulationPlan& plan, const SimulateOptions& options,
                                const SimulationObserver& observer) {
  if (!plan.truncation) return Simulate(model, plan.x0, plan.v0, options, observer);
  // On a truncated model the run's states are its modal coordinates p: every
  // state reported is the physical state to_physical p of the kept modes.
  const ModalTruncation& t = *plan.truncation;
  SimulationObserver physical = observer;
  if (observer.on_sample) {
    physical.on_sample = [&](double time, const Eigen::VectorXd& z) { observer.on_sample(time, t.PhysicalState(z)); };
  }
  if (observer.on_impact) {
    physical.on_impact = [&](const ContactEvent& ev) {
      observer.on_impact(ContactEvent{ev.t, t.PhysicalState(ev.before), t.PhysicalState(ev.after)});
    };
  }
  SimulationSummary s = Simulate(t.model, t.from_physical * plan.x0, t.from_physical * plan.v0, options, physical);
  if (s.final_state.size() > 0) s.final_state = t.PhysicalState(s.final_state);
  return s;
}

}  // namespace nsmodal
