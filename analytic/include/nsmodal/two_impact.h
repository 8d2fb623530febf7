#pragma once
// Periodic orbits with two impacts per period (paper section 2.2), in closed
// form for any number of dofs.
//
// With p = (0, r / |r|) (N = I - 2 p p') and X = (S(T) - I)^{-1}, Q_2 y = y
// reads (S(T) - I) y = 2 alpha S(T - t2) p - 2 beta p with alpha = p' S(t2) y,
// beta = p' y, so y = 2 X (alpha S(T - t2) p - beta p); substituting back
// leaves a 2 x 2 system in (alpha, beta) whose matrix is [0, 2P; 2P, 0] with
//   P(t2) = 1/2 sum_i rho_i sin(w_i (t2 - T/2)) / sin(w_i T / 2),
//   rho_i = r_i^2 / |r|^2,
// (every block of X, S is a 2 x 2 rotation-like matrix of one mode), hence
//   det A_2(t2, T) = det(S(T) - I) * 4 P(t2)^2      (checked in the tests),
// the double roots of the paper (det A_2 >= 0). NC1 is P(t2) = 0, a sum of N
// sinusoids in t2: O(N) to evaluate, and its roots are isolated with its
// derivative bounds (roots.h IsolateRoots), so none is stepped over. P is,
// up to a factor, v_c(t2) of the 1-ipp orbit of period T (one_impact.h eq.
// 21): the impacts of a 2-ipp orbit sit where the 1-ipp orbit of the same
// period has a stationary x_c, t2 = T/2 always (eq. 26: the 1-ipp orbit of
// period T/2 run twice, added exactly). On a root every (alpha, beta) solves
// the system: ker A_2 = span{X S(T - t2) p, X p}, of dimension 2 (eq. 28).
// y0 in it with x_c(0) = d and x_c(t2) = d is unique unless those two
// conditions coincide (the "bridge", paper section 4), where the orbit is
// flagged degenerate. T a multiple of a linear period (S(T) - I singular) has
// no orbit here, as for 1 impact.
#include <optional>
#include <vector>

#include "nsmodal/admissibility.h"
#include "nsmodal/flow.h"
#include "nsmodal/modal_basis.h"
#include "nsmodal/orbit.h"

namespace nsmodal {

struct TwoImpactOptions {
  // A root that the isolation could only bracket to its minimum width (a
  // tangency of P, where two roots merge at a fold of the root curve) is kept
  // when |P| there is below kernel_tol times the sum of P's amplitudes and
  // |offset| (the rigid signal's; P's round-off is ~1e-16 of that).
  double kernel_tol = 1e-11;
  AdmissibilityOptions admissibility;
};

// P(t2) for the period T as a sum of sinusoids in t2 (NC1 is P = 0), or an
// empty sum (no terms) when T is a multiple of a linear period.
//
// Two contacts (the sequence (j, k), issue 24): with p1, p2 the two contacts'
// unit impulse directions the same substitution gives the matrix
// [0, 2P; 2P, 0] with rho_i = r1_i r2_i / (|r1| |r2|) in P (p' X p = -1/2
// for any such unit p, which empties the diagonal), the kernel
// span{X S(T - t2) p2, X p1}, and NC2 on contact j at 0 and contact k at t2.
// first, second: the contacts (0-based) of the impacts at 0 and at t2.
SinusoidSum TwoImpactSignal(const AnalysisBasis& b, double period, int first = 0, int second = 0);

// With rigid-body modes (b.rigid > 0: a free mass between two walls, the
// conservative impact damper) S(T) - I is singular on them and the same
// substitution is made with X_e on the elastic modes only: the rigid
// velocity must come back, alpha p2_r = beta p1_r, so p1_r and p2_r (the
// contacts' unit impulse directions' rigid parts) must be parallel,
// p2_r = kappa p1_r, and the rigid drift must come back,
// s_r = 2 alpha (T - t2) / T p2_r. What is left is one equation,
//   F(t2) = |p2_r|^2 (2 t2 - T) / T + kappa sum_e rho_i (cot(w_i T/2) sin(w_i t2) - cos(w_i t2)),
// a sum of sinusoids with an offset and a slope (T/2 is a root: the
// symmetric orbit, Masri and Caughey's), and the kernel is the alpha
// direction plus the shifts of the rigid position, which the two NC2
// conditions fix (the minimum-norm shift: across p1_r no gap moves). A
// contact that does not move the rigid part, two that move it along
// different lines, or one contact twice: InputError naming "sequence".
void CheckTwoImpactSequence(const AnalysisBasis& b, int first, int second);

// All roots t2 in (0, T) of det A_2(., T) (with a rigid-body mode: of F,
// det A_2 being 0 for every t2), sorted, T/2 included; none when T is a
// multiple of a linear period. The isolation's work limit (1000 cells
// per half-oscillation of the fastest mode, ~25 times what it needs) is an
// internal bound: hitting it throws std::runtime_error.
std::vector<double> TwoImpactRoots(const AnalysisBasis& b, double period, const TwoImpactOptions& options = {},
                                   int first = 0, int second = 0);

// The potential orbit at a root (t2, T).
Orbit TwoImpactOrbitAt(const AnalysisBasis& b, double t2, double period, const TwoImpactOptions& options = {},
                       int first = 0, int second = 0);

// The member of the kernel of the computed A_2 at (t2, T) (its two smallest
// singular vectors, return_map.h KernelAtImpacts) with x_c(0) = d and
// x_c(t2-) = at_t2, evaluated; nullopt when the times are not in (0, T) or
// the two conditions are not independent (the smaller singular value of
// their 2 x 2 matrix at most rank_tol times the larger: a bridge). at_t2 = d
// gives the potential orbit from the SVD kernel, which TwoImpactOrbitAt takes
// where the closed form's rounding leaves it less periodic; another at_t2 a
// motion that satisfies NC1 but not NC2 (the paper's Fig. 2).
std::optional<Orbit> TwoImpactKernelOrbit(const AnalysisBasis& b, double t2, double period, double at_t2,
                                          double rank_tol, const AdmissibilityOptions& admissibility = {},
                                          int first = 0, int second = 0);

// Every potential 2-ipp orbit of period T (one per root t2).
std::vector<Orbit> TwoImpactOrbits(const AnalysisBasis& b, double period, const TwoImpactOptions& options = {},
                                   int first = 0, int second = 0);

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
