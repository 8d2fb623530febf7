// Moreau-Jean event-capturing time-stepping (theta-method), the standard of
// nonsmooth contact dynamics (Jean 1999; Acary and Brogliato 2008, ch. 10):
//   W v+ = (M - h (1 - theta) C - h^2 theta (1 - theta) K) v - h K x
//          + h (theta F(t + h) + (1 - theta) F(t)) + r,
//   W = M + h theta C + h^2 theta^2 K,   F(t) = f0 + f cos(w t),
//   x+ = x + h ((1 - theta) v + theta v+),
// with the impulse r = -e_c p (p >= 0 pushes the mass off the wall). When the
// predicted gap d - (x_c + h v_c / 2) is closed, Newton's law at velocity level
// is the one-contact LCP
//   0 <= u+ + e u  _|_  p >= 0,   u = -v_c (the gap rate),
// solved in closed form: u+ = u_free + w p with w = (W^-1)_cc.
// First order in h; impacts, Zeno accumulation and sticking are all captured by
// the LCP without events.
#include <cmath>

#include "integrators.h"
#include "nsmodal/stop.h"

namespace nsmodal::internal {

SimulationSummary SimulateMoreauJean(const ContactModel& cm, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0,
                                     const SimulateOptions& opt, const SimulationObserver& observer) {
  const Model& m = cm.model;
  const int n = m.dofs(), c = m.contact;
  const double e = m.restitution, d = m.gap, h = opt.step, th = opt.theta;
  const Eigen::MatrixXd damping = m.DampingMatrix();
  const Eigen::MatrixXd w_mat = m.mass + h * th * damping + h * h * th * th * m.stiffness;
  const Eigen::LDLT<Eigen::MatrixXd> w_ldlt(w_mat);
  const Eigen::MatrixXd b_v =
      w_ldlt.solve(m.mass - h * (1.0 - th) * damping - h * h * th * (1.0 - th) * m.stiffness);
  const Eigen::MatrixXd b_x = w_ldlt.solve(-h * m.stiffness);
  const Eigen::VectorXd w_c = w_ldlt.solve(Eigen::VectorXd::Unit(n, c));  // W^-1 e_c
  // The forces' impulse over a step: h W^-1 (f0 + f (theta cos(w (t + h)) + (1 - theta) cos(w t))).
  const bool forced = m.forcing.HasConstant() || m.forcing.HasHarmonic();
  const Eigen::VectorXd b_f0 = h * w_ldlt.solve(m.ConstantForce());
  const Eigen::VectorXd b_f = h * w_ldlt.solve(m.ForceAmplitude());
  const double w_force = m.forcing.frequency;
  const double w = w_c[c];
  SimulationSummary sum;
  Sampler sampler(opt, observer);
  Eigen::VectorXd x = x0, v = v0;
  auto state = [&] {
    Eigen::VectorXd z(2 * n);
    z << x, v;
    return z;
  };
  sampler.Emit(0.0, [&](double) { return state(); });
  const long steps = static_cast<long>(std::ceil(opt.t_end / h - 1e-9));
  const double vscale = std::sqrt(2.0 * cm.EnergyScale(x0, v0) * cm.w_cc) + 1e-300;
  // An active step with incoming gap rate below -1e-8 of the velocity scale is
  // an impact; with |u| below it, a sustained (sticking) contact.
  const double vtol = 1e-8 * vscale;
  bool in_contact = false;
  double t = 0.0;
  for (long k = 0; k < steps; ++k) {
    if (k >= opt.max_steps) {
      sum.status = SimulationStatus::kStepLimit;
      sum.message = "step limit reached at t = " + std::to_string(t);
      break;
    }
    if (observer.on_progress && k % 1000000 == 0) observer.on_progress(t);
    if (k % 1024 == 0) ThrowIfStopRequested();  // a signal (stop.h): the run unwinds
    if (k % 1024 == 0 && observer.stop_requested && observer.stop_requested()) {
      sum.status = SimulationStatus::kStopped;
      break;
    }
    const Eigen::VectorXd x_prev = x, v_prev = v;
    Eigen::VectorXd v_free = b_v * v + b_x * x;
    if (forced) {
      const double tk = k * h;
      v_free += b_f0 + (th * std::cos(w_force * (tk + h)) + (1.0 - th) * std::cos(w_force * tk)) * b_f;
    }
    double p = 0.0;
    const bool active = d - (x[c] + 0.5 * h * v[c]) <= 0.0;
    if (active) {
      const double u = -v[c];
      const double u_free = -v_free[c] + e * u;
      if (u_free < 0.0) p = -u_free / w;
    }
    v = v_free - p * w_c;
    x = x + h * ((1.0 - th) * v_prev + th * v);
    t = (k + 1) * h;
    if (p > 0.0) {
      if (-v_prev[c] < -vtol && !in_contact) {
        ++sum.impacts;
        if (observer.on_impact) {
          ContactEvent ev;
          ev.t = t;
          ev.before.resize(2 * n);
          ev.before << x_prev, v_prev;
          ev.after = state();
          observer.on_impact(ev);
        }
      } else {
        sum.sticking_time += h;
      }
      in_contact = std::abs(v[c]) <= vtol;  // held: following active steps are sticking
    } else {
      in_contact = false;
    }
    sampler.Emit(t, [&](double ts) {
      // Linear interpolation inside the step (first order, like the scheme).
      const double a = (ts - (t - h)) / h;
      Eigen::VectorXd z(2 * n);
      z << (1.0 - a) * x_prev + a * x, (1.0 - a) * v_prev + a * v;
      return z;
    });
  }
  sum.steps = std::min(steps, opt.max_steps);
  sum.final_time = t;
  sum.final_state = state();
  return sum;
}

}  // namespace nsmodal::internal
