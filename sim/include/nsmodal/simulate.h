#pragma once
// Simulation of any initial condition, any restitutions 0 <= e_j <= 1, any
// number of contacts, with or without damping and forcing (model.h), with
// three integrators behind one interface:
//   exact        closed-form flight (modal rotations for the conservative
//                model; forced_flow.h's first-order modes plus the static and
//                harmonic particular solutions otherwise), impacts isolated by conservative
//                advancement (a Taylor upper bound of x_c - d that provably
//                cannot step over a crossing), polished to root_tol;
//                K contacts: each gap searched up to the earliest crossing so far;
//   cvode        SUNDIALS CVODE (BDF or Adams) with CVodeRootInit on each
//                gap d_j - n_j . x, the Newton law at each root and CVodeReInit;
//   moreau-jean  the theta-method event-capturing time-stepper of nonsmooth
//                contact dynamics, an LCP over the contacts closing in a step
//                (one contact in closed form).
//
// Contact events at contact j (paper eq. 1-2, DESIGN.md; below x_c = n_j . x,
// v_c = n_j . v, d = d_j, e = e_j, (M^-1)_cc = n_j' M^-1 n_j):
//   impact     x_c reaches d with v_c > v_tol: v_c -> -e v_c (model.h's law);
//   graze      x_c touches d with |v_c| <= v_tol and the free acceleration
//              pulls away: no impulse, counted apart, never twice;
//   sticking   x_c = d, v_c = 0 and the free acceleration a_c pushes into the
//              wall: the mass is held (reaction lambda = a_c / (M^-1)_cc >= 0)
//              until a_c falls through 0 (with forcing, at any phase of it);
//   Zeno       for 0 < e < 1 with a_c > 0, when the rebound after an impact
//              is below the integrator's resolution (exact: inside the contact
//              band; cvode: a bounce height v+^2 / 2 a_c below its position
//              accuracy) or its flight 2 v+ / a_c is shorter than
//              zeno_flight * 2 pi / w_max, the rest of the geometric sequence
//              (time 2 v+ / (a_c (1 - e))) is summed and the mass sticks.
//   at once    contacts in their bands at the same instant are struck together
//              by Moreau's velocity-level law (contact.h): independent when the
//              Delassus matrix is diagonal, an LCP otherwise.
//   one held   one contact is held at a time, and the others are watched while
//              it is; two contacts that must be held together end the run
//              with kSolverError saying so (event_loop.h).
#include <Eigen/Dense>
#include <functional>
#include <string>
#include <vector>

#include "nsmodal/field_names.h"
#include "nsmodal/model.h"

namespace nsmodal {

enum class Integrator { kExact, kCvode, kMoreauJean };
std::string ToString(Integrator integrator);
// "exact", "cvode", "moreau-jean"; throws InputError naming `field`.
Integrator ParseIntegrator(const std::string& name, const std::string& field = "simulate.integrator");

struct SimulateOptions {
  Integrator integrator = Integrator::kExact;
  double t_end = 100.0;
  // The run's start time, in [0, t_end): the state (x0, v0) is taken at
  // t_start, so a harmonic force starts at the phase w t_start (a basin on the
  // impact section starts each motion on the wall at its impact phase). Not a
  // scene setting: Python's t_start.
  double t_start = 0.0;
  double sample_dt = 0.01;  // trajectory samples every sample_dt from t_start (0: none)
  // Trajectory samples at these times instead (ascending, in [t_start, t_end];
  // empty: the sample_dt grid). Not a scene setting: Python's t_eval.
  std::vector<double> sample_times;
  // exact: contact is reached when x_c - d >= -root_tol * max(d, amplitude of x_c).
  double root_tol = 1e-14;
  // cvode: relative and absolute tolerances, "bdf" or "adams".
  double rtol = 1e-10;
  double atol = 1e-12;
  // Adams is the default: the problem is not stiff, and at equal rtol Adams
  // was 30x more accurate than BDF over 100 periods of an orbit, in 3x fewer steps.
  std::string cvode_method = "adams";
  // cvode, e = 1, no damping and no forcing: after an impact where the energy has drifted from the
  // initial one by more than 100 rtol E0, the state is put back on the energy
  // level by scaling its velocities. Energy is invariant for e = 1; left
  // alone, CVODE's energy error per flight accumulates and, on motions whose
  // period depends on the energy, grows into a phase error quadratic in time.
  bool cvode_energy_projection = true;
  // moreau-jean: time step and theta in [1/2, 1].
  double step = 1e-3;
  double theta = 0.5;
  // Zeno truncation threshold, relative to the shortest linear period.
  double zeno_flight = 1e-9;
  // The integrator's steps (exact: conservative and grid steps together,
  // checked between flights).
  long max_steps = 2000000000;

  // Throws InputError naming the field: names("t_end"), "simulate.t_end"
  // unless the caller says where the value came from (field_names.h).
  void Validate(const FieldNames& names = FieldNames("simulate.")) const;
};

struct ContactEvent {
  double t = 0.0;
  Eigen::VectorXd before, after;  // physical (x, v)
  int contact = 0;                // 0-based index of the contact struck (the first, if several at once)
};

struct SimulationObserver {
  std::function<void(double t, const Eigen::VectorXd& z)> on_sample;  // physical (x, v)
  std::function<void(const ContactEvent&)> on_impact;
  std::function<void(double t)> on_progress;
  // Checked after every event (and every 1024 steps of Moreau-Jean): true ends
  // the run early with status kStopped.
  std::function<bool()> stop_requested;
};

enum class SimulationStatus { kFinished, kStepLimit, kSolverError, kStopped };

std::string ToString(SimulationStatus status);  // finished, step_limit, solver_error, stopped

struct SimulationSummary {
  SimulationStatus status = SimulationStatus::kFinished;
  std::string message;
  double final_time = 0.0;
  Eigen::VectorXd final_state;  // physical (x, v)
  long impacts = 0;
  long grazes = 0;
  long zeno_events = 0;
  long sticking_phases = 0;
  // The same counts per contact (index j: contact j + 1).
  std::vector<long> impacts_per_contact, grazes_per_contact, zeno_per_contact, sticking_per_contact;
  double sticking_time = 0.0;  // time with at least one contact held
  double first_zeno_time = -1.0;  // accumulation time of the first Zeno sequence
  double initial_energy = 0.0;
  double final_energy = 0.0;
  double energy_drift = 0.0;  // |E(t_end) - E(0)| / E(0)
  double wall_time_s = 0.0;
  long steps = 0;        // search steps (exact: conservative steps, N sin and cos each)
  long sweep_steps = 0;  // exact: grid steps of the impact search's sweep (first_rise.h)
};

// Throws InputError for a bad model, bad options, or an initial state beyond
// the obstacle ("simulate.initial_position").
SimulationSummary Simulate(const Model& model, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0,
                           const SimulateOptions& options, const SimulationObserver& observer = {});

}  // namespace nsmodal
