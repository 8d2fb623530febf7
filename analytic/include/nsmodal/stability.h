#pragma once
// Floquet multipliers of a periodic orbit with impacts (e = 1).
//
// Around the orbit, a perturbation is carried by the flow S(tau) between
// impacts and, across each impact, by the saltation matrix, not by N alone:
// the perturbed orbit hits the wall earlier or later. With the event surface
// h(y) = x_c - d (gradient n), the field f(y) = G y and the reset y+ = N y-,
//   Sal = N + (f(y+) - N f(y-)) n' / (n' f(y-)),       n' f(y-) = v_c- > 0.
// The monodromy from just after the impact at t = 0 around one period is
//   M = Sal_T S(T - t_m) ... Sal_2 S(t_2),
// and its eigenvalues are the Floquet multipliers. For these conservative
// families two are trivially 1 (along the flow, M f = f, and along the family:
// energy is conserved, g' M = g' with g its gradient, y0 less the rigid-body
// positions), a Jordan block whose computed eigenvalues would split by
// ~sqrt(eps); they are taken out exactly: the others are the eigenvalues of M
// restricted to {g, f(y0)}-perp (M maps g-perp to itself; the quotient by f
// is U' M U for U an orthonormal basis of that complement).
// The others come in pairs (lambda, 1/lambda) (det M = 1, symplectic): the
// orbit is stable only if all lie on the unit circle.
//
// One impact per period, any N, without forming M (O(N^2) time, O(N) memory).
// M = R + (rank 2) with R = S(T) block rotations, so with z = lambda + 1/lambda
// (z in [-2, 2] <=> |lambda| = 1) and per coupled mode z_i = 2 cos(w_i T),
// rho_i = r_i^2 / |r|^2, h_i = w_i T / 2, the characteristic polynomial is
//   det(lambda - M) = lambda^N (z - 2) Gt(z) prod_i (z - z_i),
//   Gt(z) = (z + 2) S_A(z)^2 - 2 S_B(z) S_C(z),   S_X(z) = sum_i X_i / (z - z_i),
//   A_i = rho_i, B_i = rho_i sin(2 h_i) / w_i, C_i = rho_i w_i cot(h_i)
// (the matrix determinant lemma on the rank-2 part; the double poles cancel;
// (z - 2) is the trivial pair; checked against the dense monodromy in the
// tests). Gt is real on the real axis with simple poles z_i and residues
//   g_i = 2 (z_i + 2) A_i S_A'(z_i) + A_i^2 - 2 (B_i S_C'(z_i) + C_i S_B'(z_i))
// (S' the sums without term i). Just right of z_i Gt has the sign of g_i, just
// left the opposite; Gt(z) ~ 1 / z at infinity, all roots in |z| <= 2 + 2 sum
// |g_i|. Every interval between neighbouring poles (or -2, 2, that bound)
// whose ends differ in sign holds a root; an interval without a sign change
// holds two where its extremum crosses zero, else none. If roots are still
// missing (a complex pair left the axis, |lambda| != 1), the real ones are
// polished and the rest found by Laguerre's iteration on the deflated
// polynomial P / prod(z - known), from the rootless intervals' extrema (a real
// root it finds there, one the signs did not show, is counted once).
// When the roots so accounted for number N_coupled - 1, the spectrum is
// known; otherwise the dense path is used (dense_fallback).
#include <Eigen/Dense>

#include "nsmodal/modal_basis.h"
#include "nsmodal/orbit.h"

namespace nsmodal {

struct StabilityOptions {
  // |lambda| <= 1 + tol counts as on the unit circle. With the trivial pair
  // taken out exactly the multipliers are accurate to ~1e-12 except at a
  // nontrivial collision (a +1 or -1 crossing), where a Jordan block splits
  // them by ~sqrt(eps) = 1e-8; 1e-6 leaves room and flags growth of 1e-6 per period.
  double tol = 1e-6;
  // 1 impact: every multiplier (each real root of Gt polished: O(N) per
  // evaluation, ~N roots). False: only the verdict, max_modulus and the
  // multipliers off the unit circle (O(N^2) in all, for sweeps of large N).
  bool all_multipliers = true;
};

struct Stability {
  // Sorted by decreasing modulus: all 2N, or (all_multipliers = false) the
  // ones located: every one off the unit circle, the trivial pair, and those
  // on it that the search had to locate.
  Eigen::VectorXcd multipliers;
  bool complete = true;  // multipliers holds all 2N
  double max_modulus = 0.0;
  // log(max_modulus): the rate per period at which a perturbation grows.
  double growth_per_period = 0.0;
  bool stable = false;
  // False when an impact of the orbit is a graze (|v_c-| below 1e-9 of the
  // largest contact velocity its energy allows): the saltation matrix divides
  // by v_c-, the linearisation does not exist there, and no verdict is given
  // (stable = false, the multipliers and max_modulus NaN).
  bool defined = true;
  // The 1-impact structured path could not account for every root and the
  // dense monodromy was used instead.
  bool dense_fallback = false;
};

Stability OrbitStability(const AnalysisBasis& b, const Orbit& orbit, const StabilityOptions& options = {});

// The monodromy M (dense, 2N x 2N, O(N^3)); NaN where an impact grazes.
Eigen::MatrixXd Monodromy(const AnalysisBasis& b, const Orbit& orbit);

// The saltation matrix of the elastic impact at pre-impact state y-.
// At an impact on contact j (0-based; orbit.sequence says which for each impact).
Eigen::MatrixXd SaltationMatrix(const AnalysisBasis& b, const Eigen::VectorXd& y_minus, int contact = 0);

// Gt(z) of the 1-ipp orbit of period T (above), with its poles: Gt(2) = 0 at
// a +1 crossing of a nontrivial pair, Gt(-2) = 0 at a -1 crossing (a period
// doubling). O(N) per evaluation.
struct OneImpactSecular {
  Eigen::VectorXd z, a, b, c;  // poles z_i and the coefficients of S_A, S_B, S_C (coupled modes)
  Eigen::VectorXd uncoupled;   // z_j of the modes with r_j = 0: roots of det(lambda - M) themselves
  double Value(double x) const;
};
OneImpactSecular OneImpactSecularFunction(const AnalysisBasis& b, double period, int contact = 0);

}  // namespace nsmodal
