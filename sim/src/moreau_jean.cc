// Moreau-Jean event-capturing time-stepping (theta-method), the standard of
// nonsmooth contact dynamics (Jean 1999; Acary and Brogliato 2008, ch. 10):
//   W v+ = (M - h (1 - theta) C - h^2 theta (1 - theta) K) v - h K x
//          + h (theta F(t + h) + (1 - theta) F(t)) + r,
//   W = M + h theta C + h^2 theta^2 K,   F(t) = f0 + f cos(w t),
//   x+ = x + h ((1 - theta) v + theta v+),
// with the impulse r = -H' p (p >= 0 pushes off the walls; H the normals of
// the active contacts). Contact j is active when its predicted gap
// d_j - n_j . (x + h v / 2) is closed; Newton's law at velocity level is then
// the LCP over the active contacts (lcp.h)
//   0 <= u+ + e u  _|_  p >= 0,   u = -H v (the gap rates),
//   u+ = u_free + G p,   G = H W^-1 H',
// one contact in closed form (w = n' W^-1 n).
// First order in h; impacts, Zeno accumulation and sticking are all captured by
// the LCP without events.
#include <algorithm>
#include <cmath>
#include <vector>

#include "event_loop.h"
#include "integrators.h"

namespace nsmodal::internal {

// Moreau-Jean's advance (event_loop.h's Stepper): one time step; the LCP
// resolves impacts and sticking inside it (kCaptured), so no witness fires.
class MoreauJeanStepper {
 public:
  MoreauJeanStepper(const ContactModel& cm, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0,
                    const SimulateOptions& opt)
      : cm_(cm),
        n_(cm.model.dofs()),
        k_(cm.NumContacts()),
        h_(opt.step),
        th_(opt.theta),
        w_force_(cm.model.forcing.frequency),
        forced_(cm.model.forcing.HasConstant() || cm.model.forcing.HasHarmonic()),
        steps_(static_cast<long>(std::ceil((opt.t_end - opt.t_start) / opt.step - 1e-9))),
        t0_(opt.t_start),
        in_contact_(k_, false),
        p_(Eigen::VectorXd::Zero(k_)),
        x_(x0),
        v_(v0) {
    const Model& m = cm.model;
    const double h = h_, th = th_;
    const Eigen::MatrixXd damping = m.DampingMatrix();
    const Eigen::MatrixXd w_mat = m.mass + h * th * damping + h * h * th * th * m.stiffness;
    const Eigen::LDLT<Eigen::MatrixXd> w_ldlt(w_mat);
    b_v_ = w_ldlt.solve(m.mass - h * (1.0 - th) * damping - h * h * th * (1.0 - th) * m.stiffness);
    b_x_ = w_ldlt.solve(-h * m.stiffness);
    // The forces' impulse over a step: h W^-1 (f0 + f (theta cos(w (t + h)) + (1 - theta) cos(w t))).
    b_f0_ = h * w_ldlt.solve(m.ConstantForce());
    b_f_ = h * w_ldlt.solve(m.ForceAmplitude());
    const double energy = cm.EnergyScale(x0, v0);
    for (int j = 0; j < k_; ++j) {
      w_n_.push_back(w_ldlt.solve(m.contacts[j].normal));  // W^-1 n_j
      // An active step with incoming gap rate below -1e-8 of the velocity
      // scale is an impact; with |u| below it, a sustained (sticking) contact.
      vtol_.push_back(1e-8 * (std::sqrt(2.0 * energy * cm.terms[j].w) + 1e-300));
    }
    g_.resize(k_, k_);
    for (int i = 0; i < k_; ++i) {
      for (int j = 0; j < k_; ++j) g_(i, j) = m.contacts[i].Along(w_n_[j]);
    }
  }

  bool Finished() const { return k_step_ >= steps_; }
  double Time() const { return t_; }
  long Steps() const { return k_step_; }
  std::optional<int> InitialContact() const { return std::nullopt; }

  Advance Step(Sampler& sampler) {
    Advance a;
    const double h = h_, th = th_;
    // The step's vectors live in members: no allocation per step (measured:
    // malloc and free were a quarter of a 2-dof step's time).
    x_prev_ = x_;
    v_prev_ = v_;
    const Eigen::VectorXd& x_prev = x_prev_;
    const Eigen::VectorXd& v_prev = v_prev_;
    Eigen::VectorXd& v_free = v_free_;
    v_free.noalias() = b_v_ * v_;
    v_free.noalias() += b_x_ * x_;
    if (forced_) {
      const double tk = t0_ + k_step_ * h;
      v_free += b_f0_ + (th * std::cos(w_force_ * (tk + h)) + (1.0 - th) * std::cos(w_force_ * tk)) * b_f_;
    }
    // The active contacts and their impulses (one: the closed form).
    active_.clear();
    for (int j = 0; j < k_; ++j) {
      const nsmodal::Contact& c = cm_.contact(j);
      if (c.gap - (c.Along(x_) + 0.5 * h * c.Along(v_)) <= 0.0) active_.push_back(j);
    }
    p_.head(static_cast<Eigen::Index>(active_.size())).setZero();
    if (active_.size() == 1) {
      const int j = active_[0];
      const nsmodal::Contact& c = cm_.contact(j);
      const double u = -c.Along(v_);
      const double u_free = -c.Along(v_free) + c.restitution * u;
      if (u_free < 0.0) p_[0] = -u_free / g_(j, j);
    } else if (!active_.empty()) {
      const int m = static_cast<int>(active_.size());
      Eigen::MatrixXd g(m, m);
      Eigen::VectorXd q(m);
      for (int a_i = 0; a_i < m; ++a_i) {
        const nsmodal::Contact& c = cm_.contact(active_[a_i]);
        for (int b_i = 0; b_i < m; ++b_i) g(a_i, b_i) = g_(active_[a_i], active_[b_i]);
        q[a_i] = -c.Along(v_free) - c.restitution * c.Along(v_);
      }
      const LcpSolution sol = SolveLcp(g, q);
      if (!sol.solved) {
        a.event = Advance::Event::kFailed;
        a.message = "the LCP of the active contacts failed at t = " + std::to_string(t_) + ": " + sol.message;
        return a;
      }
      p_.head(m) = sol.z;
    }
    v_ = v_free;
    for (std::size_t i = 0; i < active_.size(); ++i) {
      if (p_[static_cast<Eigen::Index>(i)] > 0.0) v_ -= p_[static_cast<Eigen::Index>(i)] * w_n_[active_[i]];
    }
    x_ += h * ((1.0 - th) * v_prev + th * v_);
    ++k_step_;
    t_ = t0_ + k_step_ * h;
    bool sticking = false;
    for (int j = 0, i = 0; j < k_; ++j) {
      const bool active = i < static_cast<int>(active_.size()) && active_[i] == j;
      const double pj = active ? p_[i++] : 0.0;
      if (pj > 0.0) {
        const nsmodal::Contact& c = cm_.contact(j);
        if (-c.Along(v_prev) < -vtol_[j] && !in_contact_[j]) {
          a.captured.push_back(j);
        } else {
          sticking = true;
        }
        in_contact_[j] = std::abs(c.Along(v_)) <= vtol_[j];  // held: following active steps are sticking
      } else {
        in_contact_[j] = false;
      }
    }
    if (!a.captured.empty()) {
      a.event = Advance::Event::kCaptured;
      a.event_states.t = t_;
      a.event_states.before.resize(2 * n_);
      a.event_states.before << x_prev, v_prev;
      a.event_states.after = Physical();
      a.event_states.contact = a.captured.front();
    } else if (sticking) {
      a.held = h;
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
  ContactKinematics Resting(int) const { return {}; }
  Eigen::VectorXd Physical() const {
    Eigen::VectorXd z(2 * n_);
    z << x_, v_;
    return z;
  }
  const std::vector<int>& Impact(int, double) const { return none_; }
  void Hold(int) {}
  void Release(int) {}
  void Restart() {}
  void Finish(SimulationSummary& sum) const {
    sum.steps = k_step_;
    sum.final_time = t_;
    sum.final_state = Physical();
  }

 private:
  const ContactModel& cm_;
  const int n_, k_;
  const double h_, th_, w_force_;
  const bool forced_;
  const long steps_;
  const double t0_;  // the start time
  std::vector<double> vtol_;
  Eigen::MatrixXd b_v_, b_x_, g_;  // g_: the Delassus matrix H W^-1 H'
  Eigen::VectorXd b_f0_, b_f_;
  std::vector<Eigen::VectorXd> w_n_;  // W^-1 n_j
  std::vector<bool> in_contact_;
  std::vector<int> active_;  // the contacts active in the step (storage reused)
  const std::vector<int> none_;  // Impact's answer: never called (the LCP captures impacts)
  Eigen::VectorXd p_;        // their impulses, p_[i] for active_[i]
  Eigen::VectorXd x_, v_;
  Eigen::VectorXd x_prev_, v_prev_, v_free_;  // the step's start and free velocity
  long k_step_ = 0;
  double t_ = t0_;
};

template NSMODAL_RUN_INTEGRATOR(MoreauJeanStepper);

}  // namespace nsmodal::internal
