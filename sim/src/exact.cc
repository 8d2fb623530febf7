// The exact event-driven integrator: closed-form flight, impacts found by
// conservative advancement (first_rise.h), the sticking phase in closed form
// (contact.h), Zeno sequences summed. One event loop over two flights:
//   ConservativeFlight  the paper's model: scaled modal state, rotations;
//   ForcedFlight        damping and forces: physical state, forced_flow.h.
#include <algorithm>
#include <cmath>
#include <optional>

#include "integrators.h"
#include "nsmodal/first_rise.h"
#include "nsmodal/stop.h"

namespace nsmodal::internal {
namespace {

struct ConservativeFlight {
  using State = Eigen::VectorXd;  // scaled modal y
  using Held = Eigen::VectorXd;   // StickingFlow's reduced modal state
  const ContactModel& cm;
  const ModalBasis& b;
  // Built at the first sticking phase: it refuses a rigid-body mode the held
  // contact does not stop, which only matters if the mass is ever held.
  std::optional<StickingFlow> stick;
  ContactSignal gap;
  SinusoidSum release;
  // The flights' impact search sweeps (first_rise.h) from this many modes
  // on: measured, a run with it against one without, 0.55 times as fast for
  // N = 2 (the grid's scalar work outweighs its saving on 2 sinusoids),
  // 1.2 times for N = 10, 2 times for N = 100.
  static constexpr int kSweepFromModes = 8;
  std::optional<SinusoidSweep> sweep;

  explicit ConservativeFlight(const ContactModel& c)
      : cm(c), b(c.basis), gap(c.basis, Eigen::VectorXd::Zero(2 * c.basis.n)) {
    gap.offset = -c.model.gap;
    if (b.n >= kSweepFromModes) sweep.emplace(b.omega);
  }
  FirstRiseResult Search(const ContactSignal& g, double horizon, double tol) {
    return sweep ? FirstRise(g, horizon, tol, *sweep) : FirstRise(g, horizon, tol);
  }
  double FastestRate() const { return b.omega.maxCoeff(); }
  State FromPhysical(const Eigen::VectorXd& z) const { return ToModal(b, z.head(b.n), z.tail(b.n)); }
  Eigen::VectorXd Physical(const State& y) const { return PhysicalOf(b, y); }
  const ContactSignal& Gap(double, const State& y) {
    gap.Reset(b, y);
    return gap;
  }
  void Fly(double, double s, State& y) const { Flow(b, s, y); }
  // x_c'' at the end of a flight, from the state there: -sum r_i w_i u_i
  // (no sin or cos; a rigid-body mode has w_i = 0).
  double Acceleration(const ContactSignal&, double, const State& y) const {
    return -(b.r.array() * b.omega.array() * y.head(b.n).array()).sum();
  }
  void Impact(double e, State& y) const { nsmodal::Impact(b, e, y); }
  double ContactVelocity(const State& y) const { return nsmodal::ContactVelocity(b, y); }
  Held Hold(double, const State& y) {
    const Eigen::VectorXd z = PhysicalOf(b, y);
    if (!stick) stick.emplace(cm);
    return stick->Enter(z.head(b.n), z.tail(b.n));
  }
  const SinusoidSum& Release(double, const Held& yr) {
    const SinusoidSum ac = stick->ContactAcceleration(yr);
    release = SinusoidSum(-ac.offset, -ac.a, -ac.b, ac.omega);  // release when -a_c rises to 0
    return release;
  }
  void FlyHeld(double, double s, Held& yr) const { stick->Advance(s, yr); }
  Eigen::VectorXd PhysicalHeld(const Held& yr) const { return stick->Physical(yr); }
};

struct ForcedFlight {
  using State = Eigen::VectorXd;  // physical (x, v)
  using Held = Eigen::VectorXd;   // (xi, xi') of the dofs other than c
  const ContactModel& cm;
  ForcedFlow flow;
  // Built at the first sticking phase: a held system resonating with the
  // forcing (undamped) only matters if the mass is ever held.
  std::optional<ForcedStickingFlow> stick;
  Eigen::RowVectorXd gap_row;
  DampedSignal gap, release;

  explicit ForcedFlight(const ContactModel& c) : cm(c), flow(c.model) {
    const int n = c.model.dofs();
    gap_row = Eigen::RowVectorXd::Zero(2 * n);
    gap_row[c.model.contact] = 1.0;
  }
  FirstRiseResult Search(const DampedSignal& g, double horizon, double tol) const { return FirstRise(g, horizon, tol); }
  double FastestRate() const { return cm.basis.omega.maxCoeff(); }
  State FromPhysical(const Eigen::VectorXd& z) const { return z; }
  Eigen::VectorXd Physical(const State& z) const { return z; }
  const DampedSignal& Gap(double t, const State& z) {
    flow.Observe(t, z, gap_row, -cm.model.gap, 0.0, gap);
    return gap;
  }
  void Fly(double t, double s, State& z) const { flow.Advance(t, s, z); }
  double Acceleration(const DampedSignal& g, double s, const State&) const { return g.Acceleration(s); }
  void Impact(double e, State& z) const {
    const int n = cm.model.dofs();
    cm.ApplyImpact(e, z.tail(n));
    if (e == 0.0) z[n + cm.model.contact] = 0.0;  // exactly, not to round-off
  }
  double ContactVelocity(const State& z) const { return z[cm.model.dofs() + cm.model.contact]; }
  Held Hold(double, const State& z) {
    if (!stick) stick.emplace(cm);
    return stick->Enter(z);
  }
  const DampedSignal& Release(double t, const Held& zr) {
    stick->Release(t, zr, release);
    return release;
  }
  void FlyHeld(double t, double s, Held& zr) const { stick->Advance(t, s, zr); }
  Eigen::VectorXd PhysicalHeld(const Held& zr) const { return stick->Physical(zr); }
};

template <typename Flight>
SimulationSummary Run(Flight& f, const ContactModel& cm, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0,
                      const SimulateOptions& opt, const SimulationObserver& observer) {
  using State = typename Flight::State;
  using Held = typename Flight::Held;
  const int n = cm.model.dofs();
  const double e = cm.model.restitution, d = cm.model.gap;
  const double zeno_flight = opt.zeno_flight * 2.0 * M_PI / f.FastestRate();
  Sampler sampler(opt, observer);
  SimulationSummary sum;

  Eigen::VectorXd z0(2 * n);
  z0 << x0, v0;
  State y = f.FromPhysical(z0);  // free-flight state
  Held yr;                       // sticking state
  bool sticking = false;
  double t = 0.0;
  sampler.Emit(0.0, [&](double) { return f.Physical(y); });
  long next_progress = 0;

  auto enter_sticking = [&] {
    f.Impact(0.0, y);  // v_c -> 0
    yr = f.Hold(t, y);
    sticking = true;
    ++sum.sticking_phases;
  };
  // At a contact (x_c within the band of half-width tol): contact.h's logic.
  // ac is the free acceleration of x_c there (the signal's second derivative).
  auto handle_contact = [&](double tol, double vtol, double ac) {
    // A rebound lower than 2 tol can never arm the next search (it arms below
    // -2 tol, first_rise.h): such a sequence is summed as Zeno, not flown as
    // unarmed micro-flights that each end tol further out (4 tol: margin for
    // the acceleration's change over the rebound).
    const ContactDecision dec = DecideContact(f.ContactVelocity(y), ac, e, {vtol, 4.0 * tol, zeno_flight});
    if (dec.outcome == ContactOutcome::kGraze) {
      ++sum.grazes;
      return;
    }
    if (dec.outcome != ContactOutcome::kHold) {
      ContactEvent ev;
      if (observer.on_impact) ev = ContactEvent{t, f.Physical(y), {}};
      f.Impact(e, y);
      ++sum.impacts;
      if (observer.on_impact) {
        ev.after = f.Physical(y);
        observer.on_impact(ev);
      }
    }
    if (dec.outcome == ContactOutcome::kImpactZeno) {
      ++sum.zeno_events;
      if (sum.first_zeno_time < 0.0) sum.first_zeno_time = t + dec.accumulation;
      sum.sticking_time -= dec.accumulation;  // held from the accumulation time on
    }
    if (dec.outcome != ContactOutcome::kImpact) enter_sticking();
  };

  while (t < opt.t_end) {
    ThrowIfStopRequested();  // a signal (stop.h): the run unwinds
    if (observer.stop_requested && observer.stop_requested()) {
      sum.status = SimulationStatus::kStopped;
      break;
    }
    if (sum.steps + sum.sweep_steps >= opt.max_steps) {
      sum.status = SimulationStatus::kStepLimit;
      sum.message = "step limit reached at t = " + std::to_string(t);
      break;
    }
    if (observer.on_progress && sum.steps >= next_progress) {
      observer.on_progress(t);
      next_progress = sum.steps + 100000;
    }
    const double horizon = opt.t_end - t;
    if (!sticking) {
      const auto* g = &f.Gap(t, y);  // x_c - d on this flight
      const double tol = opt.root_tol * std::max({d, std::abs(g->offset), g->bound[0]});
      const double vtol = std::sqrt(2.0 * g->bound[2] * tol);
      if (t == 0.0 && g->Position(0.0) >= -tol && (g->Velocity(0.0) > vtol || (std::abs(g->Velocity(0.0)) <= vtol &&
                                                                              g->Acceleration(0.0) > 0.0))) {
        handle_contact(tol, vtol, g->Acceleration(0.0));  // the initial state is a contact
        if (sticking) continue;
        g = &f.Gap(t, y);
      }
      const FirstRiseResult r = f.Search(*g, horizon, tol);
      sum.steps += r.steps;
      sum.sweep_steps += r.sweep_steps;
      if (sampler.active()) {
        const State y_start = y;
        const double t_start = t;
        sampler.Emit(t + r.s, [&](double ts) {
          State yy = y_start;
          f.Fly(t_start, ts - t_start, yy);
          return f.Physical(yy);
        });
      }
      f.Fly(t, r.s, y);
      t = r.found ? t + r.s : (r.s >= horizon ? opt.t_end : t + r.s);
      if (r.stalled) {
        sum.status = SimulationStatus::kSolverError;
        sum.message = "impact search stalled at a degenerate tangency at t = " + std::to_string(t);
        break;
      }
      if (r.found) handle_contact(tol, vtol, f.Acceleration(*g, r.s, y));
    } else {
      const auto& g = f.Release(t, yr);  // -a_c: released when it rises to 0
      const double tol = opt.root_tol * std::max(std::abs(g.offset), g.bound[0]);
      const FirstRiseResult r = FirstRise(g, horizon, tol);
      sum.steps += r.steps;
      const Held yr_start = yr;
      const double t_start = t;
      sampler.Emit(t + r.s, [&](double ts) {
        Held yy = yr_start;
        f.FlyHeld(t_start, ts - t_start, yy);
        return f.PhysicalHeld(yy);
      });
      f.FlyHeld(t, r.s, yr);
      sum.sticking_time += r.s;
      t = r.found ? t + r.s : opt.t_end;
      if (r.stalled) {
        sum.status = SimulationStatus::kSolverError;
        sum.message = "release search stalled at t = " + std::to_string(t);
        break;
      }
      if (r.found) {
        y = f.FromPhysical(f.PhysicalHeld(yr));
        sticking = false;
      }
    }
  }
  sum.final_time = t;
  sum.final_state = sticking ? f.PhysicalHeld(yr) : f.Physical(y);
  return sum;
}

}  // namespace

SimulationSummary SimulateExact(const ContactModel& cm, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0,
                                const SimulateOptions& opt, const SimulationObserver& observer) {
  if (cm.model.Conservative()) {
    ConservativeFlight flight(cm);
    return Run(flight, cm, x0, v0, opt, observer);
  }
  ForcedFlight flight(cm);
  return Run(flight, cm, x0, v0, opt, observer);
}

}  // namespace nsmodal::internal
