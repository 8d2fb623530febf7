#pragma once
// Modal truncation with a bound (issue 12: "model no more than a scene
// needs"). The k lowest linear modes of a model, as a model of k dofs that
// every part of nsmodal takes as it is (simulation, analysis, forcing).
//
// With the M-orthonormal modes Phi (x = Phi q), the kept coordinates
// q_K = (q_1..q_k) and r_K their contact row (x_c = r_K . q_K in the kept
// model), the reduced coordinates are p = |r_K| Q q_K, Q the orthogonal
// (Householder) matrix whose first row is r_K / |r_K|. Then p_0 = x_c, and
//   M_r = I / |r_K|^2,  K_r = Q diag(w_K^2) Q' / |r_K|^2,
//   C_r = Q Phi_K' C Phi_K Q' / |r_K|^2,  f_r = Q Phi_K' f / |r_K|,
// contact dof 0, the same gap and restitution: the Galerkin projection of the
// model on its first k modes, whose impulse at an impact acts along r_K as in
// the full model. x is recovered as Phi_K q_K = to_physical p.
//
// The bound. The neglected modes carry x_c^N = sum_{i > k} r_i q_i of the full
// model's contact displacement. By Cauchy-Schwarz,
//   |x_c^N| <= sqrt(sum_{i > k} r_i^2 / w_i^2) sqrt(sum_{i > k} w_i^2 q_i^2)
//           <= sqrt(2 E f_res),   f_res = sum_{i > k} r_i^2 / w_i^2,
// E the full model's energy (each neglected mode holds at most E of it).
// f_res is the residual flexibility at the contact: (K^-1)_cc minus the kept
// modes' share sum_{i <= k} r_i^2 / w_i^2 (K^-1 = Phi diag(w^-2) Phi').
// Unforced, with e <= 1, E never exceeds its initial value, so
// ContactBound(E0) bounds the neglected share of x_c over a whole motion of
// the full model. It bounds what the truncated model leaves out, not the
// distance between a truncated and a full run: impacts couple the modes, and
// a run on k modes meets the obstacle at other times (see the README's
// convergence study).
#include <Eigen/Dense>

#include "nsmodal/model.h"

namespace nsmodal {

struct ModalTruncation {
  Model model;                     // k dofs; dof 0 is x_c
  Eigen::MatrixXd to_physical;     // N x k: x = to_physical p (v likewise)
  Eigen::MatrixXd from_physical;   // k x N: p = from_physical x, the kept modes' part of x
  int kept = 0;                    // k
  int dofs = 0;                    // N
  double highest_kept_frequency = 0.0;      // w_k (rad/s)
  double lowest_neglected_frequency = 0.0;  // w_{k+1}, infinity when none is neglected
  double residual_flexibility = 0.0;        // f_res (m/N), 0 when none is neglected
  // sqrt(2 E f_res): the most the neglected modes can add to x_c in a state
  // of the full model with energy E (J).
  double ContactBound(double energy) const;
  // The full model's state (x, v), 2N, of a state (p, p') of the truncated one, 2k.
  Eigen::VectorXd PhysicalState(const Eigen::VectorXd& z) const;
};

// The first `modes` modes (the rigid-body modes and at least one elastic
// mode, at most N; InputError naming `field` otherwise). Throws InputError as
// Validate does on a bad model.
ModalTruncation TruncateModes(const Model& full, int modes, const std::string& field = "modes");

// The truncation a face asks for with a number of modes as given (a flag's
// real, a setting's whole number): InputError naming `field` unless it is a
// whole number of at most kMaxDofs in size, then as TruncateModes (the
// range the model allows). The one check of `orbits --modes` and of
// simulate's modes.
ModalTruncation TruncateModesAsGiven(const Model& full, double modes, const std::string& field);

// The fewest modes whose ContactBound(energy) is at most `tolerance` (m):
// InputError naming `field` when tolerance is not > 0 or energy not >= 0.
int ModesForContactBound(const Model& full, double energy, double tolerance,
                         const std::string& field = "contact_tolerance");
// TruncateModes(full, ModesForContactBound(...)) on one eigen-decomposition.
ModalTruncation TruncateForContactBound(const Model& full, double energy, double tolerance,
                                        const std::string& field = "contact_tolerance");

}  // namespace nsmodal
