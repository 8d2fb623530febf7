#pragma once
// Periodic forced responses (DESIGN.md "Damping and forcing"): orbits of
//   M x'' + C x' + K x = f0 + a f_hat cos(w t)
// with period P = n 2 pi / w and m impacts per period, (m, n) = (impacts, periods).
//
// Unknowns: the impact times t_1 < t_2 < ... < t_m < t_1 + P, written as
// u = (phi, tau_1, ..., tau_{m-1}) with phi = w t_1 the forcing phase at the
// first impact and tau_i = t_{i+1} - t_i (tau_m = P - sum tau_i). Flight is
// affine in the state (forced_flow.h): z(t + s) = z_p(t + s) + E(s) (z(t) - z_p(t)),
// and the Newton impact law is linear, z+ = R z-. So for given times the
// state just after the first impact is the fixed point of an affine map,
//   z_1+ = A z_1+ + b,   A = R E(tau_m) R E(tau_{m-1}) ... R E(tau_1),
// one linear solve (I - A is regular when the model is damped or e < 1:
// then no multiplier is 1 generically), and the m conditions
//   x_c(t_i-) = d,  i = 1..m
// close the system: Newton on u with the state eliminated exactly.
//
// Rigid-body modes (an impact damper's free mass, issue 24): a shift of the
// free part's position, z -> z + (Phi_0 c, 0), is a fixed direction of every
// flight and impact, so I - A is singular and solvable only when the free
// part's momentum closes over the period. The state is then the solution of
// the bordered system
//   [I - A, (0, Phi_0); (Phi_0' M, 0), 0] (z; sigma) = (b; 0)
// (sigma: the jump of the free part's velocity the period would need), plus
// (Phi_0 c, 0), with Phi_0 each mode scaled to a largest displacement of 1;
// the unknowns gain the r shifts c and the residuals the r drifts sigma P
// (lengths: the shift of the free part, how far it would drift in a period),
// so Newton stays square. Each rigid-body mode must be moved by a contact
// struck (n_{j_i} . Phi_0 not all 0), or its shift is free.
//
// With several contacts (issue 24) the orbit has an impact sequence
// (j_1, ..., j_m): impact i strikes contact j_i, with R = R_{j_i} and the
// condition n_{j_i} . x(t_i-) = d_{j_i}; one contact, x_c = n . x, is the
// sequence (1, ..., 1).
// Admissibility (as for free orbits, paper section 2): every flight stays
// on every contact's side, n_j . x(t) <= d_j strictly inside (checked by the
// guaranteed search of first_rise.h on the flight's DampedSignal, not by
// sampling), and every impact arrives towards its wall (v_c(t_i-) > 0).
// Stability: the monodromy just after the first impact,
//   Phi = S_1 E(tau_m) S_m ... S_2 E(tau_1),
// with the saltation matrix of an impact under a time-dependent field,
//   S = R + (f(t, z+) - R f(t, z-)) e_c' / v_c(t-)
// (f the vector field at the impact time, e_c' z = n_{j_i} . x); multipliers = eig(Phi).
#include <Eigen/Dense>
#include <optional>
#include <string>
#include <vector>

#include "nsmodal/forced_flow.h"
#include "nsmodal/model.h"

namespace nsmodal {

// Limits of the (m, n) nsmodal searches: m <= kMaxResponseImpacts,
// n <= kMaxResponsePeriods ((0, 1) is the non-impacting linear response).
inline constexpr int kMaxResponseImpacts = 8;
inline constexpr int kMaxResponsePeriods = 16;

struct ForcedOrbit {
  int impacts = 0, periods = 1;
  // The contact of each impact (0-based), m entries: all 0 with one contact.
  std::vector<int> sequence;
  double frequency = 0.0;  // w
  double amplitude = 0.0;  // a = max_i |f_i| of the harmonic force
  double period = 0.0;     // P = n 2 pi / w
  Eigen::VectorXd u;       // (phi, tau_1, ..., tau_{m-1}, then the r rigid shifts c)
  std::vector<double> times;                   // t_1 in [0, 2 pi / w), t_1 < ... < t_m < t_1 + P
  std::vector<Eigen::VectorXd> before, after;  // physical (x, v) at each impact
  double residual = 0.0;   // max_i |n_{j_i} . x(t_i-) - d_{j_i}|
  // Over one period:
  double energy = 0.0;     // mean mechanical energy (1/P) int E dt, E = v'Mv/2 + x'Kx/2
  double max_xc = 0.0;     // max x_c = n_1 . x, contact 1's (d_1 when contact 1 is struck)
  double min_impact_velocity = 0.0;  // min_i v_c(t_i-) towards the wall struck: > 0 when every impact arrives
  // max of n_j . x - d_j at interior maxima of the flights over every
  // contact j (-inf: none): > 0 where a flight passes a wall (NC3), 0 at a grazing.
  double max_interior_gap = 0.0;
  double work = 0.0;         // int v'(f0 + f cos(w t)) dt
  double dissipated = 0.0;   // int v'C v dt
  double impact_loss = 0.0;  // sum_i E(t_i-) - E(t_i+)
  bool admissible = false;
  std::string verdict;     // "admissible", or why not
  Eigen::VectorXcd multipliers;
  double max_multiplier = 0.0;
  bool stable = false;     // max |multiplier| < 1
};

// The least gap among the contacts a sequence strikes (empty: contact 1's):
// the length a response's residuals are measured in.
double LeastGapStruck(const Model& model, const std::vector<int>& sequence);

// One response problem: the model at one frequency and forcing amplitude.
class ForcedProblem {
 public:
  // Throws InputError: "forcing.amplitude" (no harmonic force to scale),
  // "forcing.frequency" (w <= 0 or an undamped resonance), "impacts"/"periods"
  // (an impossible (m, n)), "sequence" (a contact that does not exist),
  // "system" (undamped with e = 1 on every contact struck: the responses are
  // not isolated).
  // `sequence`: the contact of each impact (0-based, 1 to kMaxResponseImpacts
  // entries); the first form is the sequence (0, ..., 0) of m impacts.
  ForcedProblem(const Model& model, int impacts, int periods, double frequency, double amplitude);
  ForcedProblem(const Model& model, const std::vector<int>& sequence, int periods, double frequency, double amplitude);

  int impacts() const { return m_; }
  // The size of u and of the residual: m plus the rigid-body modes.
  int unknowns() const { return m_ + rigid_; }
  const std::vector<int>& sequence() const { return sequence_; }
  // The length the residuals are measured in: LeastGapStruck.
  double gap_scale() const { return gap_scale_; }
  // The model at this frequency and amplitude (the one the orbits solve).
  const Model& model() const { return model_; }
  double period() const { return period_; }
  // The fastest rate of a flight: max(max |lambda| over the flow's eigenvalues,
  // w). The work of Orbit (quadrature panels, NC3, maxima) grows as
  // period() * fastest_rate(); the constructor refuses it beyond
  // 2 pi AnalysisBasis::kMaxPeriodRatio.
  double fastest_rate() const { return fastest_; }
  // n_{j_i} . x(t_i-) - d_{j_i} for i = 1..m, then the drifts sigma P;
  // false outside the domain (a flight <= 0, or I - A, or the bordered
  // system, singular).
  bool Residual(const Eigen::VectorXd& u, Eigen::VectorXd& r) const;
  // Newton from u0 (finite-difference Jacobian), at most max_iterations;
  // converged when max |r| <= tol * gap_scale(). nullopt when it leaves the domain or
  // does not converge.
  std::optional<Eigen::VectorXd> Solve(Eigen::VectorXd u0, int max_iterations = 30, double tol = 1e-13) const;
  // The orbit at a solution u with its admissibility, energies and multipliers.
  ForcedOrbit Orbit(const Eigen::VectorXd& u) const;
  // Orbit(u).max_interior_gap without the rest of the orbit (a grazing
  // curve's defining condition, curve.h); nullopt outside the domain.
  std::optional<double> MaxInteriorGap(const Eigen::VectorXd& u) const;
  // The state of the orbit at time t.
  Eigen::VectorXd StateAt(const ForcedOrbit& orbit, double t) const;
  // Every solution at this (w, a) from a grid of starts (m = 1: a scan of the
  // phase with Brent on each sign change; m >= 2: Newton from a grid), each
  // once (the same orbit from another first impact is recognised).
  std::vector<Eigen::VectorXd> FindAll() const;
  // The canonical u of an orbit: the first impact the one earliest in the
  // forcing cycle among those the sequence may start from (the rotations of
  // the sequence that leave it unchanged), phi in [0, 2 pi).
  Eigen::VectorXd Canonical(const Eigen::VectorXd& u) const;

 private:
  struct Pass {
    std::vector<double> times;
    std::vector<Eigen::VectorXd> before, after;
    Eigen::VectorXd drift;  // sigma P, one per rigid-body mode
  };
  bool Run(const Eigen::VectorXd& u, Pass& pass) const;
  Eigen::VectorXd Field(double t, const Eigen::VectorXd& z) const;
  // The largest interior maximum of a flight's gap signal g (n_j . x - d_j
  // over a flight of length tau); -inf when it has none.
  double InteriorMaximum(const DampedSignal& g, double tau) const;

  Model model_;
  std::vector<int> sequence_;
  int m_, n_, rigid_ = 0;
  double w_, amplitude_, period_, fastest_, gap_scale_ = 0.0;
  ForcedFlow flow_;
  std::vector<Eigen::MatrixXd> impact_;  // R_j, per contact
  Eigen::MatrixXd minv_k_, minv_d_;
  Eigen::VectorXd minv_f0_, minv_f_;
  // With rigid-body modes: Phi_0 scaled to a largest displacement of 1 (so c
  // and sigma P are lengths) and its coordinates (rigid_coord_ rigid_len_ =
  // I); (0, Phi_0) and (rigid_coord_, 0), the borders; G = n_{j_i} . Phi_0
  // (m x r), the gaps' shift per unit c.
  Eigen::MatrixXd rigid_len_, rigid_coord_, kick_, gauge_, gap_shift_;
};

// The non-impacting steady state (m = 0): x_s + Re[X e^{i w t}] with
// max n_j . x = n_j . x_s + |n_j . X|; admissible while that is <= d_j for every
// contact j (max_xc: contact 1's; max_interior_gap: the largest excess). With
// one rigid-body mode, x + Phi_0 c for the c that leaves the walls the most
// room (a free mass centred in its cavity: forced_orbit.cc).
ForcedOrbit LinearResponse(const Model& model, double frequency, double amplitude);

}  // namespace nsmodal
