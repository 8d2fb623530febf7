#pragma once
// Periodic orbits with two impacts per period (paper section 2.2).
//
// NC1 roots t2 of det A_2(., T) are double roots (det A_2 >= 0). They are found
// on a grid in t2 in two ways:
//  1. sign changes of the smooth signed indicator F = Pf(Q_2 - Q_2^T)
//     (return_map.h), polished by Brent to ~1e-15 relative, kept only where
//     Q_2 really has eigenvalue 1 (not -1);
//  2. where a +1 and a -1 crossing share a cell F keeps its sign; grid nodes
//     where det(Q_2 - I) is small enough that a root may be near (a provable
//     bound, two_impact.cc) are refined by minimising sigma_min(A_2) =
//     min |2 sin(theta_k/2)|, V-shaped at a root, so the minimiser (GSL Brent)
//     reaches it to ~eps/slope, not sqrt(eps).
// t2 = T/2 is always a root (eq. 26: the 1-ipp orbit of period T/2 run twice)
// and is added exactly.
// On a root ker A_2 has dimension 2 (eq. 28); y0 in it with x_c(0) = d and
// x_c(t2) = d is unique unless those two conditions coincide (the "bridge",
// paper section 4), where the orbit is flagged degenerate.
#include <vector>

#include "nsmodal/admissibility.h"
#include "nsmodal/modal_basis.h"
#include "nsmodal/orbit.h"

namespace nsmodal {

struct TwoImpactOptions {
  // Grid spacing in t2 for the sign scan: max spacing, also at most T/64.
  // Two roots closer than this may be missed; the default resolves the
  // paper's system (checked against a 10x finer grid in the tests).
  double t2_step = 0.01;
  // A candidate is an NC1 root when the smallest singular value of A_2 is
  // below this (A_2 is O(1): Q_2 is orthogonal). At a true root it is ~1e-15;
  // at a -1 crossing ~2; at a near miss (a pair approaching 1 without reaching
  // it, close to a fold of the root curve) it was seen as low as 9e-9.
  double kernel_tol = 1e-11;
  AdmissibilityOptions admissibility;
};

// All roots t2 in (0, T) of det A_2(., T), sorted, T/2 included.
std::vector<double> TwoImpactRoots(const AnalysisBasis& b, double period, const TwoImpactOptions& options = {});

// The potential orbit at a root (t2, T).
Orbit TwoImpactOrbitAt(const AnalysisBasis& b, double t2, double period, const TwoImpactOptions& options = {});

// Every potential 2-ipp orbit of period T (one per root t2).
std::vector<Orbit> TwoImpactOrbits(const AnalysisBasis& b, double period, const TwoImpactOptions& options = {});

// Pseudo-arclength continuation of the NC1 root curve through (t2, T): the
// zero set of the signed indicator F(t2, T) (return_map.h), followed in
// arclength of the (t2, T) plane, so it passes the folds where T turns back
// (the grid of TwoImpactRoots sees a fold only as two roots merging).
// Predictor along the tangent (perpendicular to grad F, by central
// differences), corrector Newton on {F = 0, tangent . (p - p_pred) = 0}.
struct BranchOptions {
  double step = 0.01;       // arclength between points in the (t2, T) plane
  int max_points = 2000;    // in each direction
  double period_min = 0.0;  // stop on leaving period_min < T < period_max
  double period_max = 1e300;
  // Stop at a point that is not a root (sigma_min(A_2) above this, e.g. the
  // curve met a -1 crossing) or where Newton needs more than 20 iterations.
  double kernel_tol = 1e-10;
  TwoImpactOptions orbit;
};
struct BranchPoint {
  double t2 = 0.0, period = 0.0;
  double arclength = 0.0;  // signed, 0 at the start
};
// sigma_min(A_2(t2, T)): round-off (~1e-15) at a root of det A_2, V-shaped
// around it.
double TwoImpactKernelResidual(const AnalysisBasis& b, double t2, double period);

// Points of the curve through the root (t2, T), ordered by arclength, in both
// directions from it. The start must be a root (TwoImpactKernelResidual <
// kernel_tol; throws InputError naming "t2" otherwise).
std::vector<BranchPoint> TwoImpactBranch(const AnalysisBasis& b, double t2, double period,
                                         const BranchOptions& options = {});

}  // namespace nsmodal
