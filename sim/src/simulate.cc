#include "nsmodal/simulate.h"

#include <chrono>
#include <cmath>

#include "integrators.h"
#include "nsmodal/error.h"
#include "nsmodal/simulate_settings.h"

namespace nsmodal {

std::string ToString(Integrator integrator) {
  switch (integrator) {
    case Integrator::kExact: return "exact";
    case Integrator::kCvode: return "cvode";
    case Integrator::kMoreauJean: return "moreau-jean";
  }
  return "?";
}

std::string ToString(SimulationStatus status) {
  switch (status) {
    case SimulationStatus::kFinished: return "finished";
    case SimulationStatus::kStepLimit: return "step_limit";
    case SimulationStatus::kSolverError: return "solver_error";
    case SimulationStatus::kStopped: return "stopped";
  }
  return "?";
}

Integrator ParseIntegrator(const std::string& name, const std::string& field) {
  if (name == "exact") return Integrator::kExact;
  if (name == "cvode") return Integrator::kCvode;
  if (name == "moreau-jean") return Integrator::kMoreauJean;
  throw InputError(field, "must be exact, cvode or moreau-jean, got '" + name + "'");
}

void SimulateOptions::Validate(const FieldNames& name) const {
  // Each setting's own range, from its declaration (simulate_settings.cc).
  for (const Setting<SimulateOptions>& s : IntegratorSettings().settings()) {
    if (s.check) s.check(s.get(*this), name(s.info.name));
  }
  // Then the settings taken together.
  if (!(t_start >= 0.0 && t_start < t_end)) {
    throw InputError(name("t_start"), "must be in [0, t_end = " + FormatValue(t_end) + "), got " + FormatValue(t_start));
  }
  const double span = t_end - t_start;
  for (std::size_t i = 0; i < sample_times.size(); ++i) {
    const double t = sample_times[i];
    if (!(t >= t_start && t <= t_end) || (i > 0 && !(t > sample_times[i - 1]))) {
      throw InputError(name("sample_times"), "must ascend strictly within [t_start = " + FormatValue(t_start) +
                                                 ", t_end = " + FormatValue(t_end) + "]; entry " +
                                                 std::to_string(i + 1) + " is " + FormatValue(t));
    }
  }
  if (sample_times.size() > 10000000) throw InputError(name("sample_times"), "has more than 1e7 times");
  if (sample_times.empty() && sample_dt > 0.0 && span / sample_dt > 1e7) {  // (sample_times replace the grid)
    throw InputError(name("sample_dt"), "gives more than 1e7 samples over t_end - t_start = " + FormatValue(span));
  }
  if (integrator == Integrator::kMoreauJean && span / step > 1e10) {
    throw InputError(name("step"), "gives more than 1e10 steps over t_end - t_start = " + FormatValue(span));
  }
  // And the two no face sets.
  if (!(zeno_flight > 0.0) || !std::isfinite(zeno_flight)) {
    throw InputError(name("zeno_flight"), "must be positive and finite, got " + FormatValue(zeno_flight));
  }
  if (max_steps <= 0) throw InputError(name("max_steps"), "must be positive");
}

SimulationSummary Simulate(const Model& model, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0,
                           const SimulateOptions& options, const SimulationObserver& observer) {
  Validate(model);
  options.Validate();
  const int n = model.dofs();
  if (x0.size() != n) {
    throw InputError("simulate.initial_position", "must have " + std::to_string(n) + " entries, got " +
                                                      std::to_string(x0.size()));
  }
  if (v0.size() != n) {
    throw InputError("simulate.initial_velocity", "must have " + std::to_string(n) + " entries, got " +
                                                      std::to_string(v0.size()));
  }
  if (!x0.allFinite()) throw InputError("simulate.initial_position", "has a non-finite entry");
  if (!v0.allFinite()) throw InputError("simulate.initial_velocity", "has a non-finite entry");
  // Beyond any wall by more than round-off of its gap.
  for (int j = 0; j < model.NumContacts(); ++j) {
    const Contact& c = model.contacts[j];
    if (c.Along(x0) > c.gap * (1.0 + 1e-12)) {
      const std::string at = model.NumContacts() > 1 || !c.shorthand ? "contact " + std::to_string(j + 1) + " (" + c.Describe() + ")" : "the obstacle at d = " + FormatValue(c.gap);
      throw InputError("simulate.initial_position",
                       c.form == Contact::Form::kDof
                           ? "x" + std::to_string(c.dof + 1) + " = " + FormatValue(x0[c.dof]) + " lies beyond " + at
                           : "lies beyond " + at + ": n . x = " + FormatValue(c.Along(x0)));
    }
  }
  const ContactModel cm(model);
  // The start's energy within the scales honoured (model.h): energies and
  // velocities of every later state stay finite.
  const double e0 = cm.EnergyOf(x0, v0);
  if (!(e0 <= kMaxEnergyScale)) {
    throw InputError(!(0.5 * v0.dot(model.mass * v0) <= kMaxEnergyScale) ? "simulate.initial_velocity"
                                                                           : "simulate.initial_position",
                     "gives an energy of " + FormatValue(e0) + "; nsmodal honours up to " +
                         FormatValue(kMaxEnergyScale) + ": rescale the units");
  }
  const auto start = std::chrono::steady_clock::now();
  SimulationSummary s;
  using internal::RunIntegrator;
  switch (options.integrator) {
    case Integrator::kExact:
      s = model.Conservative()
              ? RunIntegrator<internal::ExactStepper<internal::ConservativeFlight>>(cm, x0, v0, options, observer)
              : RunIntegrator<internal::ExactStepper<internal::ForcedFlight>>(cm, x0, v0, options, observer);
      break;
    case Integrator::kCvode: s = RunIntegrator<internal::CvodeStepper>(cm, x0, v0, options, observer); break;
    case Integrator::kMoreauJean: s = RunIntegrator<internal::MoreauJeanStepper>(cm, x0, v0, options, observer); break;
  }
  s.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  s.initial_energy = cm.EnergyOf(x0, v0);
  s.final_energy = cm.EnergyOf(s.final_state.head(n), s.final_state.tail(n));
  s.energy_drift = s.initial_energy > 0.0 ? std::abs(s.final_energy - s.initial_energy) / s.initial_energy : 0.0;
  // Never a silent NaN: a non-finite end is a failed run.
  if (s.status == SimulationStatus::kFinished && (!s.final_state.allFinite() || !std::isfinite(s.final_energy))) {
    s.status = SimulationStatus::kSolverError;
    s.message = "the state became non-finite at t = " + FormatValue(s.final_time);
  }
  return s;
}

}  // namespace nsmodal
