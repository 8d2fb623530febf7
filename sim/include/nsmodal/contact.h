#pragma once
// Contact mechanics shared by the integrators: the impact law in physical
// coordinates (one contact, or several struck at once) and the constrained
// (sticking) dynamics n_j . x = d_j, n_j . v = 0.
#include <Eigen/Dense>
#include <vector>

#include "nsmodal/flow.h"
#include "nsmodal/lcp.h"
#include "nsmodal/forced_flow.h"
#include "nsmodal/modal_basis.h"
#include "nsmodal/model.h"

namespace nsmodal {

// Contact j's terms: the direction of its impulse and its normal's rows.
struct ContactTerms {
  Eigen::VectorXd minv_n;    // M^-1 n_j: the direction of its impulse
  double w = 0.0;            // n_j' M^-1 n_j (the Delassus matrix's diagonal)
  Eigen::RowVectorXd k_row;  // n_j' M^-1 K
  Eigen::RowVectorXd d_row;  // n_j' M^-1 C
  double f0 = 0.0, f = 0.0;  // n_j . M^-1 f0, n_j . M^-1 f
};

// Several contacts struck at once (Moreau's velocity-level Newton law). With
// u_j = n_j . v the normal velocities towards the walls of the contacts
// struck (S), H their normals and G = H M^-1 H' (the Delassus matrix), the
// impulses p >= 0 act along M^-1 H': u+ = u- - G p, and
//   0 <= p  _|_  -(u+ + e u-) >= 0      (componentwise, e = each contact's e_j):
// an LCP (lcp.h). When G is diagonal (the normals M^-1-orthogonal: stops on
// different masses of a diagonal M) it decouples: each contact takes its own
// law, p_j = (1 + e_j) u_j / G_jj, in any order.
struct ContactModel {
  Model model;
  ModalBasis basis;
  Eigen::MatrixXd minv_k;   // M^-1 K
  Eigen::MatrixXd minv_d;   // M^-1 C (zero when undamped)
  Eigen::VectorXd minv_f0;  // M^-1 f0 (zero when absent)
  Eigen::VectorXd minv_f;   // M^-1 f (zero when absent)
  std::vector<ContactTerms> terms;  // one per contact
  Eigen::MatrixXd delassus;         // G = H M^-1 H' over all contacts

  explicit ContactModel(const Model& m);
  int NumContacts() const { return model.NumContacts(); }
  const Contact& contact(int j) const { return model.contacts[j]; }
  // g_j = d_j - n_j . x and the normal velocity n_j . v (> 0 moving in).
  double Gap(int j, const Eigen::Ref<const Eigen::VectorXd>& x) const {
    return model.contacts[j].gap - model.contacts[j].Along(x);
  }
  double NormalVelocity(int j, const Eigen::Ref<const Eigen::VectorXd>& v) const {
    return model.contacts[j].Along(v);
  }
  // Contact j alone: v <- v - (1 + e) u_j M^-1 n_j / w_j, so u_j -> -e u_j.
  void ApplyImpact(int j, double e, Eigen::Ref<Eigen::VectorXd> v) const;
  // The contacts of `set` struck at once, each with its restitution (or
  // `plastic`: e = 0 for all, a hold), by the law above; returns false when
  // the LCP solver failed (v unchanged).
  bool ApplyImpacts(const std::vector<int>& set, Eigen::Ref<Eigen::VectorXd> v, bool plastic = false) const;
  // The acceleration of free flight, M^-1 (f0 + f cos(w t) - C v - K x).
  Eigen::VectorXd FreeAcceleration(double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                                   const Eigen::Ref<const Eigen::VectorXd>& v) const;
  // Its normal component at contact j, n_j . a: positive pushes into the wall.
  double FreeContactAcceleration(int j, double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                                 const Eigen::Ref<const Eigen::VectorXd>& v) const;
  double EnergyOf(const Eigen::Ref<const Eigen::VectorXd>& x, const Eigen::Ref<const Eigen::VectorXd>& v) const {
    return 0.5 * v.dot(model.mass * v) + 0.5 * x.dot(model.stiffness * x);
  }
  // The energy scale of a run from (x0, v0): E(x0, v0) plus the energies of
  // the static and of the harmonic (steady-state) responses to the forces;
  // the integrators' velocity thresholds are relative to sqrt(2 scale w_j).
  double EnergyScale(const Eigen::VectorXd& x0, const Eigen::VectorXd& v0) const;
  // The largest w_j: the velocity scale's factor over all contacts.
  double MaxDelassus() const;
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

// The held subspace of contact j: n_j . x = d_j, n_j . v = 0, as
// x = x_p + Z xi with x_p = (d_j / |n_j|^2) n_j and Z an orthonormal basis of
// the other directions (for a dof contact, the other dofs' unit vectors).
struct HeldSpace {
  Eigen::MatrixXd z;       // N x (N - 1)
  Eigen::VectorXd normal;  // n_j
  double scale = 0.0;      // d_j / |n_j|^2: x_p = scale n_j
  std::vector<int> others; // a dof contact: the other dofs (Z's columns are their unit vectors)
  HeldSpace(const Contact& contact, int dofs);
  Eigen::VectorXd Particular() const { return scale * normal; }
  // xi = Z'(x - x_p) (position) or Z' v, and back: x_p + Z xi or Z xi'.
  Eigen::VectorXd Reduce(const Eigen::Ref<const Eigen::VectorXd>& y, bool position) const;
  Eigen::VectorXd Expand(const Eigen::Ref<const Eigen::VectorXd>& xi, bool position) const;
};

// The sticking phase in closed form (conservative model). With x = Z xi + x_p
// (HeldSpace), M_r = Z'MZ, K_r = Z'KZ, the held system is M_r xi'' + K_r xi + Z'K x_p = 0:
// oscillations of its own modes about xi* = -K_r^-1 Z'K x_p. The contact
// force lambda = a_j / w_j, with a_j = -n_j . M^-1 K x a constant plus a
// sum of sinusoids: the mass is released when a_j falls through 0. The
// other contacts' gaps are sums of sinusoids of the same held flow.
class StickingFlow {
 public:
  // Throws InputError naming "system.stiffness_matrix" when K_r is singular
  // (a rigid-body mode the held contact does not stop).
  StickingFlow(const ContactModel& cm, int contact);
  int reduced_dofs() const { return nr_; }
  // State on entry (physical x, v with x_c = d, v_c = 0) -> scaled reduced modal state.
  Eigen::VectorXd Enter(const Eigen::VectorXd& x, const Eigen::VectorXd& v) const;
  void Advance(double dt, Eigen::Ref<Eigen::VectorXd> yr) const;
  Eigen::VectorXd Physical(const Eigen::VectorXd& yr) const;  // (x, v)
  // a_j(s) for s >= 0 from the reduced state yr.
  SinusoidSum ContactAcceleration(const Eigen::VectorXd& yr) const;
  // n_k . x(s) - d_k of another contact k along the held flow from yr (it
  // is struck when this rises to 0).
  SinusoidSum OtherGap(int k, const Eigen::VectorXd& yr) const;
  int contact() const { return j_; }

 private:
  const ContactModel* cm_;
  int j_ = 0;
  int nr_ = 0;
  HeldSpace space_;
  Eigen::VectorXd omega_, xi_star_, rho_;
  Eigen::MatrixXd phi_, phi_inv_;
  double a0_ = 0.0;
};

// The sticking phase of a damped or forced model, in closed form: the held
// system M_r xi'' + C_r xi' + K_r xi = Z'(f0 - K x_p) + Z' f cos(w t)
// flies as a ForcedFlow, and the contact acceleration
//   a_j = n_j . M^-1 (f0 + f cos(w t) - C Z xi' - K (Z xi + x_p))
// is a DampedSignal along it: the mass is released when a_j falls through 0,
// at whatever phase of the forcing that happens.
class ForcedStickingFlow {
 public:
  ForcedStickingFlow(const ContactModel& cm, int contact);
  // Physical z = (x, v) on entry (n_j . x = d_j, n_j . v = 0) -> reduced (xi, xi').
  Eigen::VectorXd Enter(const Eigen::VectorXd& z) const;
  void Advance(double t, double s, Eigen::Ref<Eigen::VectorXd> zr) const { flow_.Advance(t, s, zr); }
  Eigen::VectorXd Physical(const Eigen::VectorXd& zr) const;  // (x, v)
  // -a_j(t + s) for s >= 0 from zr = the reduced state at t (reuses out).
  void Release(double t, const Eigen::VectorXd& zr, DampedSignal& out) const;
  // n_k . x(t + s) - d_k of another contact k along the held flow (reuses out).
  void OtherGap(int k, double t, const Eigen::VectorXd& zr, DampedSignal& out) const;
  int contact() const { return j_; }

 private:
  const ContactModel* cm_;
  int j_ = 0;
  HeldSpace space_;
  ForcedFlow flow_;
  Eigen::RowVectorXd release_row_;  // -a_c's state part
  double release_c0_ = 0.0, release_c1_ = 0.0;
};

}  // namespace nsmodal
