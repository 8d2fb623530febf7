#pragma once
// The settings of a simulation, declared once (settings.h): the integrator's
// options (SimulateOptions, simulate.h), the initial state and a modal
// truncation. The scene's [simulate] table, the `simulate` command's flags,
// Python's simulate() keywords and summary.json's settings block are made
// from these tables; validation lifts the integrator's tolerances from them.
//
// And the run a simulation request describes (the CLI and Python both call
// it): the start checked, a truncation chosen, the run on the kept modes,
// every state it reports mapped back to the N dofs.
#include <Eigen/Dense>
#include <optional>
#include <vector>

#include "nsmodal/model.h"
#include "nsmodal/settings.h"
#include "nsmodal/simulate.h"
#include "nsmodal/truncation.h"

namespace nsmodal {

// What a simulation is asked: the integrator's options, the start and the
// modes kept.
struct SimulationRequest {
  SimulateOptions options;
  std::vector<double> initial_position;  // x(0), N entries; required
  std::vector<double> initial_velocity;  // v(0), N entries; empty: at rest
  // Modal truncation (truncation.h): keep this many modes, or the fewest
  // whose bound on the neglected share of x_c is at most contact_tolerance
  // (m) at the initial energy. At most one of them.
  std::optional<long> modes;
  std::optional<double> contact_tolerance;
};

// The integrator's settings (each lists the commands that take it:
// "simulate", and "validate" for the tolerances and steps).
const SettingTable<SimulateOptions>& IntegratorSettings();
// [simulate]: the integrator's settings, the start and the truncation.
const SettingTable<SimulationRequest>& SimulateSettings();

// A simulation ready to run: the start (physical), its energy and the
// truncation chosen, if any.
struct SimulationPlan {
  Eigen::VectorXd x0, v0;  // N dofs
  double initial_energy = 0.0;
  std::optional<ModalTruncation> truncation;
};

// Checks the options and the model (InputError naming each field as the
// request's origins say: "--t-end", "simulate.t_end", "t_end") and chooses the
// truncation. Of modes and contact_tolerance, one given with a higher
// precedence than the other (a flag over a scene key) replaces it; both from
// the same face are refused.
SimulationPlan PlanSimulation(const Model& model, const Configured<SimulationRequest>& request);

// Runs the plan: on the truncated model when there is one, every state the
// observer and the summary see mapped back to the N dofs.
SimulationSummary RunSimulation(const Model& model, const SimulationPlan& plan, const SimulateOptions& options,
                                const SimulationObserver& observer = {});

}  // namespace nsmodal
