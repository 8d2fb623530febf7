// The exact event-driven integrator: closed-form modal flight, impacts found
// by conservative advancement (first_rise.h), the sticking phase in closed form
// (contact.h), Zeno sequences summed.
#include <cmath>

#include "integrators.h"
#include "nsmodal/first_rise.h"

namespace nsmodal::internal {

SimulationSummary SimulateExact(const ContactModel& cm, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0,
                                const SimulateOptions& opt, const SimulationObserver& observer) {
  const ModalBasis& b = cm.basis;
  const int n = b.n;
  const double e = cm.model.restitution, d = cm.model.gap;
  const double zeno_flight = opt.zeno_flight * 2.0 * M_PI / b.omega.maxCoeff();
  const StickingFlow stick(cm);
  Sampler sampler(opt, observer);
  SimulationSummary sum;

  Eigen::VectorXd y = ToModal(b, x0, v0);  // free-flight state
  ContactSignal g(b, y);                   // x_c - d on the current flight
  g.offset = -d;
  Eigen::VectorXd yr;                      // sticking state
  bool sticking = false;
  double t = 0.0;
  sampler.Emit(0.0, [&](double) { return PhysicalOf(b, y); });
  long next_progress = 0;

  auto enter_sticking = [&] {
    Impact(b, 0.0, y);  // v_c -> 0 exactly
    const Eigen::VectorXd z = PhysicalOf(b, y);
    yr = stick.Enter(z.head(n), z.tail(n));
    sticking = true;
    ++sum.sticking_phases;
  };
  // At a contact (x_c within the band of half-width tol): contact.h's logic.
  // ac is the free acceleration of x_c there (the signal's second derivative).
  auto handle_contact = [&](double tol, double vtol, double ac) {
    const ContactDecision dec = DecideContact(ContactVelocity(b, y), ac, e, {vtol, tol, zeno_flight});
    if (dec.outcome == ContactOutcome::kGraze) {
      ++sum.grazes;
      return;
    }
    if (dec.outcome != ContactOutcome::kHold) {
      ContactEvent ev;
      if (observer.on_impact) ev = ContactEvent{t, PhysicalOf(b, y), {}};
      Impact(b, e, y);
      ++sum.impacts;
      if (observer.on_impact) {
        ev.after = PhysicalOf(b, y);
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
    if (observer.stop_requested && observer.stop_requested()) {
      sum.status = SimulationStatus::kStopped;
      break;
    }
    if (sum.steps >= opt.max_steps) {
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
      g.Reset(b, y);
      const double tol = opt.root_tol * std::max(d, g.bound[0]);
      const double vtol = std::sqrt(2.0 * g.bound[2] * tol);
      if (t == 0.0 && g.Position(0.0) >= -tol && (g.Velocity(0.0) > vtol || (std::abs(g.Velocity(0.0)) <= vtol &&
                                                                              g.Acceleration(0.0) > 0.0))) {
        handle_contact(tol, vtol, g.Acceleration(0.0));  // the initial state is a contact
        if (sticking) continue;
        g.Reset(b, y);
      }
      const FirstRiseResult r = FirstRise(g, horizon, tol);
      sum.steps += r.steps;
      if (sampler.active()) {
        const Eigen::VectorXd y_start = y;
        const double t_start = t;
        sampler.Emit(t + r.s, [&](double ts) {
          Eigen::VectorXd yy = y_start;
          Flow(b, ts - t_start, yy);
          return PhysicalOf(b, yy);
        });
      }
      Flow(b, r.s, y);
      t = r.found ? t + r.s : (r.s >= horizon ? opt.t_end : t + r.s);
      if (r.stalled) {
        sum.status = SimulationStatus::kSolverError;
        sum.message = "impact search stalled at a degenerate tangency at t = " + std::to_string(t);
        break;
      }
      if (r.found) handle_contact(tol, vtol, g.Acceleration(r.s));
    } else {
      const SinusoidSum ac = stick.ContactAcceleration(yr);
      SinusoidSum g(-ac.offset, -ac.a, -ac.b, ac.omega);  // release when -a_c rises to 0
      const double tol = opt.root_tol * std::max(std::abs(ac.offset), ac.bound[0]);
      const FirstRiseResult r = FirstRise(g, horizon, tol);
      sum.steps += r.steps;
      const Eigen::VectorXd yr_start = yr;
      const double t_start = t;
      sampler.Emit(t + r.s, [&](double ts) {
        Eigen::VectorXd yy = yr_start;
        stick.Advance(ts - t_start, yy);
        return stick.Physical(yy);
      });
      stick.Advance(r.s, yr);
      sum.sticking_time += r.s;
      t = r.found ? t + r.s : opt.t_end;
      if (r.stalled) {
        sum.status = SimulationStatus::kSolverError;
        sum.message = "release search stalled at t = " + std::to_string(t);
        break;
      }
      if (r.found) {
        const Eigen::VectorXd z = stick.Physical(yr);
        y = ToModal(b, z.head(n), z.tail(n));
        sticking = false;
      }
    }
  }
  sum.final_time = t;
  sum.final_state = sticking ? stick.Physical(yr) : PhysicalOf(b, y);
  return sum;
}

}  // namespace nsmodal::internal
