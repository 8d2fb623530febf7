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
  // the LCP solver failed (v unchanged). `struck`, when given, receives the
  // contacts given an impulse (p_j > 0).
  bool ApplyImpacts(const std::vector<int>& set, Eigen::Ref<Eigen::VectorXd> v, bool plastic = false,
                    std::vector<int>* struck = nullptr) const;
  // The contacts of `set` made held: the impulses along M^-1 H' that bring
  // every normal velocity of the set to 0, v <- v - M^-1 H' G_S^-1 H v. A
  // hold is bilateral: the plastic LCP above leaves a contact moving away
  // (slower than the resolution that decided the hold) as it was, and the
  // held flow, which keeps n_j . v constant, would carry that residual on
  // (a pair of held contacts drifted off one wall at 1e-5 m/s for seconds).
  // False (v untouched) when G_S is singular to round-off (its reciprocal
  // condition number below 1e-12: normals dependent, which no held set can
  // be).
  bool HoldVelocity(const std::vector<int>& set, Eigen::Ref<Eigen::VectorXd> v) const;
  // Which contacts of `set` (at rest on their walls at time t, state z =
  // (x, v)) are held: Moreau's law at the acceleration level, the forces
  // 0 <= lambda _|_ G_S lambda - a >= 0 (a the free normal accelerations,
  // > 0 pushing in; an LCP, lcp.h), those with lambda > 0. Deciding one at a
  // time on the motion held by the others depends on the order: holding a
  // contact whose free acceleration pushes in can make a coupled one's force
  // negative. False (held untouched) when the LCP solver failed.
  bool HeldByForces(const std::vector<int>& set, double t, const Eigen::Ref<const Eigen::VectorXd>& z,
                    std::vector<int>& held) const;
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
  // G_S = H M^-1 H' over the contacts of `set`, in its order.
  Eigen::MatrixXd DelassusBlock(const std::vector<int>& set) const;
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

// The held subspace of a set S of contacts (several held at once):
// n_j . x = d_j and n_j . v = 0 for j in S, as x = x_p + Z xi with
// x_p = sum_j c_j n_j, c = (H H')^-1 d_S (H the normals of S as rows; for one
// contact c = d_j / |n_j|^2, for stops on distinct dofs c_j = d_j), and Z an
// orthonormal basis of the other directions (for dof contacts, the other
// dofs' unit vectors). The normals of S must be independent (InputError
// naming "contact" otherwise: the held set would not be a subspace of that
// dimension).
struct HeldSpace {
  std::vector<int> set;              // the held contacts, ascending
  Eigen::MatrixXd z;                 // N x (N - |S|)
  std::vector<Eigen::VectorXd> normals;
  std::vector<double> coefficients;  // c_j: x_p = sum c_j n_j
  std::vector<int> others;           // dof contacts: the other dofs (Z's columns are their unit vectors)
  HeldSpace(const ContactModel& cm, std::vector<int> held);
  int Reduced() const { return static_cast<int>(z.cols()); }
  Eigen::VectorXd Particular() const;  // x_p
  // A x_p as sum_j c_j (A n_j), and row . (A x_p) as sum_j c_j (row . A n_j):
  // for one contact exactly the products the one-contact flow made.
  Eigen::VectorXd Times(const Eigen::MatrixXd& a) const;
  double RowTimes(const Eigen::RowVectorXd& row, const Eigen::MatrixXd& a) const;
  // xi = Z'(x - x_p) (position) or Z' v, and back: x_p + Z xi or Z xi'.
  Eigen::VectorXd Reduce(const Eigen::Ref<const Eigen::VectorXd>& y, bool position) const;
  Eigen::VectorXd Expand(const Eigen::Ref<const Eigen::VectorXd>& xi, bool position) const;
};

// The contact forces of a held set S as rows: lambda_S = W H M^-1 (f - K x - C v)
// with W = G_S^-1 (G_S = H M^-1 H'), and for one contact W = 1 (its a_j =
// w_j lambda_j: the sign is the force's, the scale the one-contact flow's).
// rows(i) = W_i H M^-1 (N entries): the i-th held contact's.
Eigen::MatrixXd HeldForceRows(const ContactModel& cm, const std::vector<int>& set);

// The sticking phase in closed form (conservative model). With x = Z xi + x_p
// (HeldSpace), M_r = Z'MZ, K_r = Z'KZ, the held system is M_r xi'' + K_r xi + Z'K x_p = 0:
// oscillations of its own modes about xi* = -K_r^-1 Z'K x_p. Each held
// contact's force (HeldForceRows: -row K x) is a constant plus a sum of
// sinusoids: that contact is released when it falls through 0. The other
// contacts' gaps are sums of sinusoids of the same held flow.
class StickingFlow {
 public:
  // Throws InputError naming "system.stiffness_matrix" when K_r is singular
  // (a rigid-body mode the held contacts do not stop).
  StickingFlow(const ContactModel& cm, std::vector<int> held);
  int reduced_dofs() const { return nr_; }
  const std::vector<int>& held() const { return space_.set; }
  // State on entry (physical x, v on the held walls) -> scaled reduced modal state.
  Eigen::VectorXd Enter(const Eigen::VectorXd& x, const Eigen::VectorXd& v) const;
  void Advance(double dt, Eigen::Ref<Eigen::VectorXd> yr) const;
  Eigen::VectorXd Physical(const Eigen::VectorXd& yr) const;  // (x, v)
  // The force of the i-th held contact (as HeldForceRows scales it), s >= 0.
  SinusoidSum ContactAcceleration(int i, const Eigen::VectorXd& yr) const;
  // n_k . x(s) - d_k of another contact k along the held flow from yr (it
  // is struck when this rises to 0).
  SinusoidSum OtherGap(int k, const Eigen::VectorXd& yr) const;

 private:
  const ContactModel* cm_;
  int nr_ = 0;
  HeldSpace space_;
  Eigen::VectorXd omega_, xi_star_;
  Eigen::MatrixXd phi_, phi_inv_, rho_;  // rho_: one column per held contact
  Eigen::VectorXd a0_;
};

// The sticking phase of a damped or forced model, in closed form: the held
// system M_r xi'' + C_r xi' + K_r xi = Z'(f0 - K x_p) + Z' f cos(w t)
// flies as a ForcedFlow, and each held contact's force
//   row_i (f0 + f cos(w t) - C Z xi' - K (Z xi + x_p))   (HeldForceRows)
// is a DampedSignal along it: that contact is released when it falls
// through 0, at whatever phase of the forcing that happens.
class ForcedStickingFlow {
 public:
  ForcedStickingFlow(const ContactModel& cm, std::vector<int> held);
  const std::vector<int>& held() const { return space_.set; }
  // Physical z = (x, v) on entry (on the held walls) -> reduced (xi, xi').
  Eigen::VectorXd Enter(const Eigen::VectorXd& z) const;
  void Advance(double t, double s, Eigen::Ref<Eigen::VectorXd> zr) const { flow_.Advance(t, s, zr); }
  Eigen::VectorXd Physical(const Eigen::VectorXd& zr) const;  // (x, v)
  // minus the i-th held contact's force at t + s, s >= 0, from zr = the reduced state at t (reuses out).
  void Release(int i, double t, const Eigen::VectorXd& zr, DampedSignal& out) const;
  // n_k . x(t + s) - d_k of another contact k along the held flow (reuses out).
  void OtherGap(int k, double t, const Eigen::VectorXd& zr, DampedSignal& out) const;

 private:
  const ContactModel* cm_;
  HeldSpace space_;
  ForcedFlow flow_;
  std::vector<Eigen::RowVectorXd> release_rows_;  // minus each force's state part
  std::vector<double> release_c0_, release_c1_;
};

}  // namespace nsmodal
