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

#include "event_loop.h"
#include "integrators.h"

namespace nsmodal::internal {

// Moreau-Jean's advance (event_loop.h's Stepper): one time step; the LCP
// resolves impacts and sticking inside it (kCaptured), so no witness fires.
class MoreauJeanStepper {
 public:
  MoreauJeanStepper(const ContactModel& cm, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0,
                    const SimulateOptions& opt)
      : n_(cm.model.dofs()),
        c_(cm.model.contact),
        e_(cm.model.restitution),
        d_(cm.model.gap),
        h_(opt.step),
        th_(opt.theta),
        w_force_(cm.model.forcing.frequency),
        forced_(cm.model.forcing.HasConstant() || cm.model.forcing.HasHarmonic()),
        steps_(static_cast<long>(std::ceil(opt.t_end / opt.step - 1e-9))),
        // An active step with incoming gap rate below -1e-8 of the velocity scale is
        // an impact; with |u| below it, a sustained (sticking) contact.
        vtol_(1e-8 * (std::sqrt(2.0 * cm.EnergyScale(x0, v0) * cm.w_cc) + 1e-300)),
        x_(x0),
        v_(v0) {
    const Model& m = cm.model;
    const double h = h_, th = th_;
    const Eigen::MatrixXd damping = m.DampingMatrix();
    const Eigen::MatrixXd w_mat = m.mass + h * th * damping + h * h * th * th * m.stiffness;
    const Eigen::LDLT<Eigen::MatrixXd> w_ldlt(w_mat);
    b_v_ = w_ldlt.solve(m.mass - h * (1.0 - th) * damping - h * h * th * (1.0 - th) * m.stiffness);
    b_x_ = w_ldlt.solve(-h * m.stiffness);
    w_c_ = w_ldlt.solve(Eigen::VectorXd::Unit(n_, c_));  // W^-1 e_c
    // The forces' impulse over a step: h W^-1 (f0 + f (theta cos(w (t + h)) + (1 - theta) cos(w t))).
    b_f0_ = h * w_ldlt.solve(m.ConstantForce());
    b_f_ = h * w_ldlt.solve(m.ForceAmplitude());
    w_ = w_c_[c_];
  }

  bool Finished() const { return k_ >= steps_; }
  double Time() const { return t_; }
  long Steps() const { return k_; }
  std::optional<int> InitialContact() const { return std::nullopt; }

  Advance Step(Sampler& sampler) {
    Advance a;
    const double h = h_, th = th_;
    const Eigen::VectorXd x_prev = x_, v_prev = v_;
    Eigen::VectorXd v_free = b_v_ * v_ + b_x_ * x_;
    if (forced_) {
      const double tk = k_ * h;
      v_free += b_f0_ + (th * std::cos(w_force_ * (tk + h)) + (1.0 - th) * std::cos(w_force_ * tk)) * b_f_;
    }
    double p = 0.0;
    const bool active = d_ - (x_[c_] + 0.5 * h * v_[c_]) <= 0.0;
    if (active) {
      const double u = -v_[c_];
      const double u_free = -v_free[c_] + e_ * u;
      if (u_free < 0.0) p = -u_free / w_;
    }
    v_ = v_free - p * w_c_;
    x_ = x_ + h * ((1.0 - th) * v_prev + th * v_);
    ++k_;
    t_ = k_ * h;
    if (p > 0.0) {
      if (-v_prev[c_] < -vtol_ && !in_contact_) {
        a.event = Advance::Event::kCaptured;
        a.event_states.t = t_;
        a.event_states.before.resize(2 * n_);
        a.event_states.before << x_prev, v_prev;
        a.event_states.after = Physical();
      } else {
        a.held = h;
      }
      in_contact_ = std::abs(v_[c_]) <= vtol_;  // held: following active steps are sticking
    } else {
      in_contact_ = false;
    }
    sampler.Emit(t_, [&](double ts) {
      // Linear interpolation inside the step (first order, like the scheme).
      const double s = (ts - (t_ - h)) / h;
      Eigen::VectorXd z(2 * n_);
      z << (1.0 - s) * x_prev + s * x_, (1.0 - s) * v_prev + s * v_;
      return z;
    });
    return a;
  }

  // Never called: the LCP decides inside the step.
  ContactKinematics Contact(int) const { return {}; }
  Eigen::VectorXd Physical() const {
    Eigen::VectorXd z(2 * n_);
    z << x_, v_;
    return z;
  }
  void Impact(int, double) {}
  void Hold(int) {}
  void Release(int) {}
  void Restart() {}
  void Finish(SimulationSummary& sum) const {
    sum.steps = k_;
    sum.final_time = t_;
    sum.final_state = Physical();
  }

 private:
  const int n_, c_;
  const double e_, d_, h_, th_, w_force_;
  const bool forced_;
  const long steps_;
  const double vtol_;
  Eigen::MatrixXd b_v_, b_x_;
  Eigen::VectorXd w_c_, b_f0_, b_f_;
  double w_ = 0.0;
  Eigen::VectorXd x_, v_;
  bool in_contact_ = false;
  long k_ = 0;
  double t_ = 0.0;
};

template NSMODAL_RUN_INTEGRATOR(MoreauJeanStepper);

}  // namespace nsmodal::internal
