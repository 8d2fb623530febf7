#pragma once
// Modal basis of the free flight (paper eqs. 4-8), in a scaled form that makes
// every map of the analysis orthogonal for e = 1.
//
// K phi = w^2 M phi with Phi' M Phi = I, Phi' K Phi = diag(w_i^2); x = Phi q.
// The scaled modal state is y = (u, s) with u_i = w_i q_i and s_i = dq_i/dt, so
//   energy E = v'Mv/2 + x'Kx/2 = |y|^2 / 2,
//   free flight is a rotation by w_i t in each plane (u_i, s_i) (eq. 8),
//   the impact is s <- s - (1 + e) r (r.s)/|r|^2 with r = row c of Phi (eq. 10-12);
// for e = 1 the impact is a reflection, so S(t) and N are orthogonal.
//
// Rigid-body modes (w_i = 0, K semi-definite; the first `rigid` modes): u_i = q_i
// (there is no w_i to scale by) and the flight is the free drift
// u_i <- u_i + t s_i, exactly. The energy is then |y|^2 / 2 less the rigid
// u_i^2 / 2 (flow.h Energy); the analysis (AnalysisBasis) takes such systems
// only for the sequences it can solve, the simulator flies them all.
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "nsmodal/model.h"

namespace nsmodal {

// Contact j in the scaled modal coordinates: n_j . x = r_j . q with
// r_j = Phi' n_j, and its impact s <- s - (1 + e_j) r_j (r_j . s) / |r_j|^2.
struct ModalContact {
  Eigen::VectorXd r;             // Phi' n_j
  Eigen::VectorXd r_over_omega;  // r_i / u_scale_i: n_j . x = sum (r_i / w_i) u_i (+ rigid r_i q_i)
  double r_norm2 = 0.0;          // |r|^2 = n_j' M^-1 n_j
  double gap = 1.0;              // d_j
  // An earlier contact whose r is parallel to this one's (to 1e-14: two walls
  // of one dof), whose signal's critical points are this one's; -1: none.
  int parallel = -1;
};

struct ModalBasis {
  int n = 0;                // dofs
  int rigid = 0;            // rigid-body modes: w_i = 0 for i < rigid
  Eigen::VectorXd omega;    // w_i, ascending
  Eigen::VectorXd u_scale;  // u_i = u_scale_i q_i: w_i, or 1 for a rigid-body mode
  Eigen::MatrixXd phi;      // Phi, columns M-orthonormal
  Eigen::MatrixXd phi_inv;  // Phi^{-1} = Phi' M
  // Contact 1's projection (the one-contact analysis's; x_c = n_1 . x):
  Eigen::VectorXd r;        // Phi' n_1 (row c of Phi for the paper's x_c <= d): x_c = sum r_i q_i
  Eigen::VectorXd r_over_omega;  // r_i / u_scale_i: x_c = sum (r_i / w_i) u_i (+ rigid r_i q_i)
  double r_norm2 = 0.0;     // |r|^2 = n_1' M^-1 n_1 ((M^{-1})_cc)
  double gap = 1.0;
  std::vector<ModalContact> contacts;  // every contact's, contacts[0] as above

  // Linear periods T_i = 2 pi / w_i (infinite for a rigid-body mode).
  Eigen::VectorXd Periods() const;
};

ModalBasis MakeModalBasis(const Model& model);

// The basis of the periodic-orbit analysis (paper sections 1-4: return maps,
// orbits, transitions, bridges, stability). Periodic orbits with impacts exist
// only for e = 1: energy is lost at every impact when e < 1 (paper section 1).
// So an AnalysisBasis can only be built from a model with e = 1 (the
// constructor throws InputError naming system.restitution), every analysis
// function takes one, and kRestitution is the one place the analysis states e.
// Nonsmooth modes are those of the conservative system: a model with damping
// or forcing is refused too (InputError naming "system" or "forcing"). A model
// with a rigid-body mode (K semi-definite) is refused with one contact
// ("system.stiffness_matrix"): no periodic orbit has impacts there (each
// impact pushes the drift's momentum away from the obstacle and no flight
// brings it back). With several contacts (a free mass in a cavity: the impact
// damper) the two-impact sequences (a, b), a != b, have orbits
// (two_impact.h); every analysis that needs K definite (1-impact families,
// transitions, bridges, explore, the 2-impact kernel residual, indicator and
// continuation) calls RequireElastic first. (ReturnMap, MatrixA and
// KernelAtImpacts stay general linear algebra: with a rigid mode the shift
// is always in ker A_m.)
struct AnalysisBasis : ModalBasis {
  static constexpr double kRestitution = 1.0;
  // Periods the analysis honours, relative to the shortest linear period
  // T_min: below 1e-6 T_min the flow is the identity to round-off (the
  // "orbits" are artefacts); above 1e5 T_min the NC3 search on one flight
  // scans more than 1e5 oscillations of the fastest mode.
  static constexpr double kMinPeriodRatio = 1e-6;
  static constexpr double kMaxPeriodRatio = 1e5;
  explicit AnalysisBasis(const Model& model);
  // Throws InputError naming `field` when T is outside that range.
  void CheckPeriod(double period, const std::string& field = "period") const;
  // Throws InputError naming system.stiffness_matrix when the basis has a
  // rigid-body mode: `what` (e.g. "1-impact orbits") needs K definite.
  void RequireElastic(const std::string& what) const;
};

// Conversions between the physical state z = (x, v) and the scaled modal y.
Eigen::VectorXd ToModal(const ModalBasis& b, const Eigen::VectorXd& x, const Eigen::VectorXd& v);
Eigen::VectorXd PositionOf(const ModalBasis& b, const Eigen::VectorXd& y);
Eigen::VectorXd VelocityOf(const ModalBasis& b, const Eigen::VectorXd& y);
Eigen::VectorXd PhysicalOf(const ModalBasis& b, const Eigen::VectorXd& y);  // (x, v)

}  // namespace nsmodal
