#pragma once
// Contact mechanics shared by the integrators: the impact law in physical
// coordinates and the constrained (sticking) dynamics x_c = d, v_c = 0.
#include <Eigen/Dense>

#include "nsmodal/flow.h"
#include "nsmodal/forced_flow.h"
#include "nsmodal/modal_basis.h"
#include "nsmodal/model.h"

namespace nsmodal {

struct ContactModel {
  Model model;
  ModalBasis basis;
  Eigen::MatrixXd minv_k;   // M^-1 K
  Eigen::MatrixXd minv_d;   // M^-1 C (zero when undamped)
  Eigen::VectorXd minv_f0;  // M^-1 f0 (zero when absent)
  Eigen::VectorXd minv_f;   // M^-1 f (zero when absent)
  Eigen::VectorXd minv_c;   // M^-1 e_c
  double w_cc = 0.0;        // (M^-1)_cc

  explicit ContactModel(const Model& m);
  // v <- v - (1 + e) v_c M^-1 e_c / (M^-1)_cc, so v_c -> -e v_c.
  void ApplyImpact(double e, Eigen::Ref<Eigen::VectorXd> v) const;
  // The acceleration of free flight, M^-1 (f0 + f cos(w t) - C v - K x).
  Eigen::VectorXd FreeAcceleration(double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                                   const Eigen::Ref<const Eigen::VectorXd>& v) const;
  // Its contact component a_c: positive pushes the contact dof into the wall.
  double FreeContactAcceleration(double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                                 const Eigen::Ref<const Eigen::VectorXd>& v) const;
  double EnergyOf(const Eigen::Ref<const Eigen::VectorXd>& x, const Eigen::Ref<const Eigen::VectorXd>& v) const {
    return 0.5 * v.dot(model.mass * v) + 0.5 * x.dot(model.stiffness * x);
  }
  // The energy scale of a run from (x0, v0): E(x0, v0) plus the energies of
  // the static and of the harmonic (steady-state) responses to the forces;
  // the integrators' velocity thresholds are relative to sqrt(2 scale (M^-1)_cc).
  double EnergyScale(const Eigen::VectorXd& x0, const Eigen::VectorXd& v0) const;
};

// The contact logic of the event-driven integrators (simulate.h), given what
// each integrator can resolve.
struct ContactResolution {
  double vtol;         // a contact slower than this is a graze or a hold, not an impact
  double height;       // a rebound lower than this (v+^2 / 2 a_c) is below resolution
  double zeno_flight;  // a rebound shorter than this (2 v+ / a_c) is truncated
};
enum class ContactOutcome {
  kGraze,        // no impulse: the free acceleration pulls away
  kHold,         // arrives at rest, pushed in: sticking, no impact
  kImpact,       // an impact, then free flight
  kImpactHold,   // an impact with no rebound (e = 0 or v+ <= vtol), pushed in: sticking
  kImpactZeno,   // an impact starting an accumulation: summed, then sticking
};
struct ContactDecision {
  ContactOutcome outcome;
  double accumulation = 0.0;  // kImpactZeno: time to the accumulation point, 2 v+ / (a_c (1 - e))
};
// vc: contact velocity before the contact (> 0 moving in); ac: free contact acceleration.
ContactDecision DecideContact(double vc, double ac, double e, const ContactResolution& r);

// The sticking phase in closed form (conservative model). With x = Z xi + d e_c (Z: the other
// dofs), M_r = Z'MZ, K_r = Z'KZ, the held system is M_r xi'' + K_r xi + d Z'K e_c = 0:
// oscillations of its own modes about xi* = -d K_r^-1 Z'K e_c. The contact
// force lambda = a_c / (M^-1)_cc, with a_c = -(M^-1 K x)_c a constant plus a
// sum of sinusoids: the mass is released when a_c falls through 0.
class StickingFlow {
 public:
  // Throws InputError naming "system.stiffness_matrix" when K_r is singular
  // (a rigid-body mode the held contact does not stop).
  explicit StickingFlow(const ContactModel& cm);
  int reduced_dofs() const { return nr_; }
  // State on entry (physical x, v with x_c = d, v_c = 0) -> scaled reduced modal state.
  Eigen::VectorXd Enter(const Eigen::VectorXd& x, const Eigen::VectorXd& v) const;
  void Advance(double dt, Eigen::Ref<Eigen::VectorXd> yr) const;
  Eigen::VectorXd Physical(const Eigen::VectorXd& yr) const;  // (x, v)
  // a_c(s) for s >= 0 from the reduced state yr.
  SinusoidSum ContactAcceleration(const Eigen::VectorXd& yr) const;

 private:
  const ContactModel* cm_;
  int nr_ = 0;
  std::vector<int> others_;
  Eigen::VectorXd omega_, xi_star_, rho_;
  Eigen::MatrixXd phi_, phi_inv_;
  double a0_ = 0.0;
};

// The sticking phase of a damped or forced model, in closed form: the held
// system M_r xi'' + C_r xi' + K_r xi = Z'(f0 - K e_c d) + Z' f cos(w t)
// flies as a ForcedFlow, and the contact acceleration
//   a_c = [M^-1 (f0 + f cos(w t) - C Z xi' - K (Z xi + d e_c))]_c
// is a DampedSignal along it: the mass is released when a_c falls through 0,
// at whatever phase of the forcing that happens.
class ForcedStickingFlow {
 public:
  explicit ForcedStickingFlow(const ContactModel& cm);
  // Physical z = (x, v) on entry (x_c = d, v_c = 0) -> reduced (xi, xi').
  Eigen::VectorXd Enter(const Eigen::VectorXd& z) const;
  void Advance(double t, double s, Eigen::Ref<Eigen::VectorXd> zr) const { flow_.Advance(t, s, zr); }
  Eigen::VectorXd Physical(const Eigen::VectorXd& zr) const;  // (x, v)
  // -a_c(t + s) for s >= 0 from zr = the reduced state at t (reuses out).
  void Release(double t, const Eigen::VectorXd& zr, DampedSignal& out) const;

 private:
  const ContactModel* cm_;
  std::vector<int> others_;
  ForcedFlow flow_;
  Eigen::RowVectorXd release_row_;  // -a_c's state part
  double release_c0_ = 0.0, release_c1_ = 0.0;
};

}  // namespace nsmodal
