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
// families two are trivially 1 (along the flow and along the family); the
// others come in pairs (lambda, 1/lambda): the orbit is stable only if all lie
// on the unit circle.
#include <Eigen/Dense>

#include "nsmodal/modal_basis.h"
#include "nsmodal/orbit.h"

namespace nsmodal {

struct Stability {
  Eigen::MatrixXd monodromy;
  Eigen::VectorXcd multipliers;  // sorted by decreasing modulus
  double max_modulus = 0.0;
  // log(max_modulus): the rate per period at which a perturbation grows.
  double growth_per_period = 0.0;
  bool stable = false;
  // False when an impact of the orbit is a graze (|v_c-| below 1e-9 of the
  // largest contact velocity its energy allows): the saltation matrix divides
  // by v_c-, the linearisation does not exist there, and no verdict is given
  // (stable = false, the multipliers and max_modulus NaN).
  bool defined = true;
};

// tol: |lambda| <= 1 + tol counts as on the unit circle. The trivial pair at 1
// is a Jordan block, whose computed eigenvalues split by ~sqrt(eps) = 1e-8;
// 1e-6 leaves room for that and still flags growth of 1e-6 per period.
Stability OrbitStability(const AnalysisBasis& b, const Orbit& orbit, double tol = 1e-6);

// The saltation matrix of the elastic impact at pre-impact state y-.
Eigen::MatrixXd SaltationMatrix(const AnalysisBasis& b, const Eigen::VectorXd& y_minus);

}  // namespace nsmodal
