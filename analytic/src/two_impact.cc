#include "nsmodal/two_impact.h"

#include <algorithm>
#include <cmath>

#include "nsmodal/error.h"
#include "nsmodal/flow.h"
#include "nsmodal/return_map.h"
#include "nsmodal/roots.h"

namespace nsmodal {

namespace {

// sigma_min(A_2) = min_k |2 sin(theta_k / 2)|: V-shaped (not quadratic) at a
// root, so golden section reaches it to ~eps / slope, not sqrt(eps). (GSL's
// Brent minimiser steps no finer than sqrt(eps) |x| and stops at ~1e-8.)
double SmallestSingularValue(const AnalysisBasis& b, double t2, double period) {
  return Eigen::JacobiSVD<Eigen::MatrixXd>(MatrixA(b, {t2}, period)).singularValues().minCoeff();
}

// Minimises sigma_min(A_2) on [lo, hi] from mid; returns the minimiser.
double MinimizeSigma(const AnalysisBasis& b, double period, double lo, double mid, double hi) {
  return MinimizeOn([&](double t) { return SmallestSingularValue(b, t, period); }, lo, mid, hi);
}

}  // namespace

std::vector<double> TwoImpactRoots(const AnalysisBasis& b, double period, const TwoImpactOptions& options) {
  const double half = 0.5 * period;
  // An even number of cells so that T/2 is a grid node.
  int cells = static_cast<int>(std::ceil(period / std::min(options.t2_step, period / 64.0)));
  cells += cells % 2;
  auto indicator = [&](double t2) { return TwoImpactIndicator(b, t2, period); };
  const Eigen::MatrixXd id = Eigen::MatrixXd::Identity(2 * b.n, 2 * b.n);
  // Grid nodes 0..cells: the signed indicator F and det(Q - I) >= 0. The end
  // nodes t2 = 0 and t2 = T (coincident impacts, Q = N S(T) N) bracket the
  // roots of short flights next to an impact (T just above a k T_i).
  std::vector<double> t(cells + 1), f(cells + 1), det(cells + 1);
  for (int j = 0; j <= cells; ++j) {
    t[j] = period * j / cells;
    const Eigen::MatrixXd q = ReturnMap(b, {t[j]}, period);
    f[j] = Pfaffian(q - q.transpose());
    det[j] = (q - id).determinant();
  }
  std::vector<double> roots{half};
  auto accept = [&](double root) {
    if (root < 1e-9 * period || root > (1.0 - 1e-9) * period) return;  // coincident impacts
    for (double r : roots) {
      if (std::abs(r - root) <= 1e-9 * period) return;
    }
    if (SmallestSingularValue(b, root, period) < options.kernel_tol) roots.push_back(root);
  };
  // 1. Sign changes of F: a pair of eigenvalues crossing +1 (kept) or -1 (rejected).
  for (int j = 1; j <= cells; ++j) {
    if ((f[j - 1] < 0.0) != (f[j] < 0.0) || f[j] == 0.0) accept(f[j] == 0.0 ? t[j] : PolishRoot(indicator, t[j - 1], t[j]));
  }
  // 2. A +1 and a -1 crossing in one cell leave F's sign unchanged. sigma_min(A_2)
  // is 2 w_max-Lipschitz in t2 (|dQ/dt2| <= 2 w_max, Weyl), and the eigenvalue
  // pair makes det(Q - I) <= 4^(N-1) sigma_min^2: where det exceeds
  // 4^(N-1) (2 w_max h)^2 no root lies within h. Elsewhere, away from the roots
  // already found, minimise sigma_min(A_2) around the node.
  const double h = period / cells;
  const double reach = 2.0 * b.omega.maxCoeff() * h;
  const double det_bound = std::pow(4.0, b.n - 1) * reach * reach;
  for (int j = 1; j < cells; ++j) {
    if (det[j] > det_bound) continue;
    bool explained = false;
    for (double r : roots) explained = explained || std::abs(r - t[j]) <= 2.0 * h;
    if (explained) continue;
    const double lo = t[j - 1], hi = t[j + 1];
    if (!(SmallestSingularValue(b, t[j], period) < std::min(SmallestSingularValue(b, lo, period),
                                                             SmallestSingularValue(b, hi, period)))) {
      continue;  // the minimum is at a neighbouring node, tried on its own
    }
    accept(MinimizeSigma(b, period, lo, t[j], hi));
  }
  std::sort(roots.begin(), roots.end());
  return roots;
}

Orbit TwoImpactOrbitAt(const AnalysisBasis& b, double t2, double period, const TwoImpactOptions& options) {
  const int dim = 2 * b.n;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(MatrixA(b, {t2}, period), Eigen::ComputeFullV);
  const Eigen::VectorXd k1 = svd.matrixV().col(dim - 1);
  const Eigen::VectorXd k2 = svd.matrixV().col(dim - 2);
  // NC2: x_c(0) = d and x_c(t2-) = d for y0 = alpha k1 + beta k2.
  Eigen::VectorXd s1 = k1, s2 = k2;
  Flow(b, t2, s1);
  Flow(b, t2, s2);
  Eigen::Matrix2d c;
  c << ContactPosition(b, k1), ContactPosition(b, k2), ContactPosition(b, s1), ContactPosition(b, s2);
  const Eigen::Vector2d rhs(b.gap, b.gap);
  Eigen::JacobiSVD<Eigen::Matrix2d> csvd(c, Eigen::ComputeFullU | Eigen::ComputeFullV);
  // The two conditions coincide (rank 1) when the smaller singular value is at
  // round-off level of the larger: then a line of y0 satisfies NC2.
  const bool degenerate = csvd.singularValues()[1] <= 1e-10 * csvd.singularValues()[0];
  Eigen::Vector2d coef;
  if (degenerate) {
    csvd.setThreshold(1e-10);
    coef = csvd.solve(rhs);  // the minimum-norm member of the continuum
  } else {
    coef = c.partialPivLu().solve(rhs);
  }
  Orbit orbit = EvaluateOrbit(b, coef[0] * k1 + coef[1] * k2, {t2}, period, options.admissibility);
  orbit.degenerate = degenerate;
  return orbit;
}

std::vector<Orbit> TwoImpactOrbits(const AnalysisBasis& b, double period, const TwoImpactOptions& options) {
  std::vector<Orbit> out;
  for (double t2 : TwoImpactRoots(b, period, options)) out.push_back(TwoImpactOrbitAt(b, t2, period, options));
  return out;
}

namespace {

// grad F by central differences: F is a polynomial in trigonometric functions
// of t2 and T with O(1) coefficients, so h = 1e-6 gives ~1e-10 relative error,
// enough for Newton's direction and the tangent.
Eigen::Vector2d IndicatorGradient(const AnalysisBasis& b, double t2, double period) {
  const double h = 1e-6;
  return {(TwoImpactIndicator(b, t2 + h, period) - TwoImpactIndicator(b, t2 - h, period)) / (2 * h),
          (TwoImpactIndicator(b, t2, period + h) - TwoImpactIndicator(b, t2, period - h)) / (2 * h)};
}

// Newton on {F = 0, tangent . (p - pred) = 0} from pred; false if it fails.
bool Correct(const AnalysisBasis& b, const Eigen::Vector2d& tangent, Eigen::Vector2d& p) {
  const Eigen::Vector2d pred = p;
  for (int it = 0; it < 20; ++it) {
    const double f = TwoImpactIndicator(b, p[0], p[1]);
    const Eigen::Vector2d g = IndicatorGradient(b, p[0], p[1]);
    Eigen::Matrix2d j;
    j << g[0], g[1], tangent[0], tangent[1];
    const Eigen::Vector2d r(f, tangent.dot(p - pred));
    const Eigen::Vector2d dp = j.partialPivLu().solve(-r);
    if (!dp.allFinite()) return false;
    p += dp;
    if (dp.norm() < 1e-14 * (1.0 + p.norm())) return true;
  }
  return false;
}

}  // namespace

double TwoImpactKernelResidual(const AnalysisBasis& b, double t2, double period) {
  return SmallestSingularValue(b, t2, period);
}

std::vector<BranchPoint> TwoImpactBranch(const AnalysisBasis& b, double t2, double period, const BranchOptions& options) {
  if (!(SmallestSingularValue(b, t2, period) < options.kernel_tol)) {
    throw InputError("t2", "(t2, T) = (" + std::to_string(t2) + ", " + std::to_string(period) +
                               ") is not a root of det A_2: no branch to follow");
  }
  std::vector<BranchPoint> sides[2];
  for (int side = 0; side < 2; ++side) {
    Eigen::Vector2d p(t2, period);
    Eigen::Vector2d g = IndicatorGradient(b, p[0], p[1]);
    Eigen::Vector2d tangent = Eigen::Vector2d(-g[1], g[0]).normalized() * (side == 0 ? 1.0 : -1.0);
    double s = 0.0;
    for (int k = 0; k < options.max_points; ++k) {
      Eigen::Vector2d q = p + options.step * tangent;
      if (!Correct(b, tangent, q)) break;
      if (!(q[0] > 0.0 && q[0] < q[1] && q[1] > options.period_min && q[1] < options.period_max)) break;
      if (!(SmallestSingularValue(b, q[0], q[1]) < options.kernel_tol)) break;
      s += (q - p).norm();
      sides[side].push_back({q[0], q[1], side == 0 ? s : -s});
      g = IndicatorGradient(b, q[0], q[1]);
      Eigen::Vector2d next = Eigen::Vector2d(-g[1], g[0]).normalized();
      tangent = next.dot(tangent) >= 0.0 ? next : Eigen::Vector2d(-next);  // keep the direction
      p = q;
    }
  }
  std::vector<BranchPoint> out(sides[1].rbegin(), sides[1].rend());
  out.push_back({t2, period, 0.0});
  out.insert(out.end(), sides[0].begin(), sides[0].end());
  return out;
}

}  // namespace nsmodal
