#include "nsmodal/two_impact.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "nsmodal/error.h"
#include "nsmodal/model.h"
#include "nsmodal/flow.h"
#include "nsmodal/return_map.h"
#include "nsmodal/roots.h"

namespace nsmodal {

namespace {

// sigma_min(A_2) = min_k |2 sin(theta_k / 2)|: V-shaped (not quadratic) at a
// root. The continuation below checks its points with it.
double SmallestSingularValue(const AnalysisBasis& b, double t2, double period) {
  return Eigen::JacobiSVD<Eigen::MatrixXd>(MatrixA(b, {t2}, period)).singularValues().minCoeff();
}

// |sin(w_i T / 2)| below this (relative) makes T a multiple of T_i to round-off.
constexpr double kSingularPeriod = 1e-14;

}  // namespace

SinusoidSum TwoImpactSignal(const AnalysisBasis& b, double period, int first, int second) {
  // rho_i sin(w (t - T/2)) / (2 sin(w T/2)) = (rho_i / 2) (cot(w T/2) sin(w t) - cos(w t)),
  // rho_i = r1_i r2_i / (|r1| |r2|) (r_i^2 / |r|^2 for one contact).
  const ModalContact &c1 = b.contacts[first], &c2 = b.contacts[second];
  const double norms = first == second ? c1.r_norm2 : std::sqrt(c1.r_norm2 * c2.r_norm2);
  Eigen::VectorXd a(b.n), c(b.n);
  for (int i = 0; i < b.n; ++i) {
    const double h = 0.5 * b.omega[i] * period;
    const double half_rho = 0.5 * c1.r[i] * c2.r[i] / norms;
    if (!(std::abs(std::sin(h)) > kSingularPeriod)) return {};
    a[i] = -half_rho;
    c[i] = half_rho * std::cos(h) / std::sin(h);
  }
  return SinusoidSum(0.0, std::move(a), std::move(c), b.omega);
}

std::vector<double> TwoImpactRoots(const AnalysisBasis& b, double period, const TwoImpactOptions& options, int first,
                                   int second) {
  const SinusoidSum p = TwoImpactSignal(b, period, first, second);
  if (p.omega.size() == 0) return {};
  // Two contacts that share no mode (r1_i r2_i = 0 for every i: decoupled
  // parts) make P vanish for every t2: each wall's 1-impact orbit at any
  // phase, a continuum of orbits, not isolated roots.
  if (first != second && !(p.a.cwiseAbs().maxCoeff() > 0.5e-14)) {
    throw InputError("sequence", "contacts " + std::to_string(first + 1) + " and " + std::to_string(second + 1) +
                                     " move no common mode (decoupled parts): every t2 is a root, the orbits of "
                                     "the sequence are each contact's 1-impact orbits at any phase; ask for "
                                     "each contact's family instead");
  }
  const double half = 0.5 * period;
  const double min_width = 1e-12 * period;
  // As CheckSegment (admissibility.cc): P has about w_max T / pi roots, each
  // isolated in ~40 halvings.
  const long max_cells = static_cast<long>(std::min(1e9, 1000.0 * (2.0 + p.omega.maxCoeff() * period / M_PI)));
  bool complete = true;
  const std::vector<double> found = IsolateRoots(
      [&p](double t) {
        double d[4];
        p.Derivatives(t, d);
        return std::make_pair(d[0], d[1]);
      },
      p.bound[1], p.bound[2], 0.0, period, min_width, max_cells, &complete);
  if (!complete) {
    throw std::runtime_error("2-ipp roots at T = " + FormatValue(period) + ": the isolation of the roots of P(t2) hit its " +
                             "work limit of " + std::to_string(max_cells) + " cells");
  }
  std::vector<double> roots{half};  // exactly (eq. 26)
  for (double t2 : found) {
    // Coincident impacts (t2 at 0 or T) are 1-ipp orbits; T/2 is already in.
    if (t2 < 1e-9 * period || t2 > (1.0 - 1e-9) * period || std::abs(t2 - half) <= 1e-9 * period) continue;
    // A bracket left at its minimum width is a tangency only if P vanishes there.
    if (std::abs(p.Position(t2)) <= options.kernel_tol * p.bound[0]) roots.push_back(t2);
  }
  std::sort(roots.begin(), roots.end());
  return roots;
}

Orbit TwoImpactOrbitAt(const AnalysisBasis& b, double t2, double period, const TwoImpactOptions& options, int first,
                       int second) {
  const int n = b.n;
  const ModalContact &c1 = b.contacts[first], &c2 = b.contacts[second];
  // ker A_2 = span{X S(T - t2) p2, X p1} (two_impact.h; p1 = p2 = p for one
  // contact); per mode, with X = [-1/2, -k; k, -1/2], k = cot(w T/2) / 2 and
  // p_i = r_i / |r| in s:
  //   X p = p_i (-k, -1/2),  X S(tau) p = p_i (-sin(w tau)/2 - k cos(w tau), k sin(w tau) - cos(w tau)/2).
  Eigen::MatrixXd kernel(2 * n, 2);
  const double norm1 = std::sqrt(c1.r_norm2), norm2 = std::sqrt(c2.r_norm2);
  for (int i = 0; i < n; ++i) {
    const double p1 = c1.r[i] / norm1, p2 = c2.r[i] / norm2;
    const double k = 0.5 * std::cos(0.5 * b.omega[i] * period) / std::sin(0.5 * b.omega[i] * period);
    const double c = std::cos(b.omega[i] * (period - t2)), s = std::sin(b.omega[i] * (period - t2));
    kernel(i, 0) = p2 * (-0.5 * s - k * c);
    kernel(n + i, 0) = p2 * (k * s - 0.5 * c);
    kernel(i, 1) = -p1 * k;
    kernel(n + i, 1) = -0.5 * p1;
  }
  // An orthonormal basis of the kernel, so that the rank test below compares
  // like with like whatever the scale of X.
  const Eigen::MatrixXd q = Eigen::HouseholderQR<Eigen::MatrixXd>(kernel).householderQ() *
                            Eigen::MatrixXd::Identity(2 * n, 2);
  const Eigen::VectorXd k1 = q.col(0), k2 = q.col(1);
  // NC2: the first contact's x_c(0) = d and the second's x_c(t2-) = d for y0 = alpha k1 + beta k2.
  Eigen::VectorXd s1 = k1, s2 = k2;
  Flow(b, t2, s1);
  Flow(b, t2, s2);
  Eigen::Matrix2d c;
  c << ContactPosition(b, c1, k1), ContactPosition(b, c1, k2), ContactPosition(b, c2, s1), ContactPosition(b, c2, s2);
  const Eigen::Vector2d rhs(c1.gap, c2.gap);
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
  Orbit orbit = EvaluateOrbit(b, coef[0] * k1 + coef[1] * k2, {t2}, period, options.admissibility, {first, second});
  orbit.degenerate = degenerate;
  // Within ~1e-4 of a multiple of a linear period the closed form divides by
  // sin(w T / 2) ~ 1e-3, whose rounding is not the flow's: the orbit is then
  // periodic to a few 1e-12 only (measured on the paper's system). The kernel
  // of the computed A_2 (its two smallest singular vectors) is consistent with
  // the flow to ~5e-14: taken instead where it does better, at O(N^3) for
  // those few orbits.
  constexpr double kRefineAbove = 1e-12;
  if (!degenerate && orbit.periodicity_residual > kRefineAbove) {
    const std::optional<Orbit> refined =
        TwoImpactKernelOrbit(b, t2, period, c2.gap, 1e-10, options.admissibility, first, second);
    if (refined && refined->periodicity_residual < orbit.periodicity_residual && refined->nc2_residual <= 1e-12) {
      return *refined;
    }
  }
  return orbit;
}

std::optional<Orbit> TwoImpactKernelOrbit(const AnalysisBasis& b, double t2, double period, double at_t2,
                                          double rank_tol, const AdmissibilityOptions& admissibility, int first,
                                          int second) {
  KernelContacts kc;
  if (!KernelAtImpacts(b, {t2}, period, 2, kc, {first, second})) return std::nullopt;
  const Eigen::Matrix2d c = kc.c;
  const Eigen::Vector2d s = Eigen::JacobiSVD<Eigen::Matrix2d>(c).singularValues();
  if (!(s[1] > rank_tol * s[0])) return std::nullopt;
  return EvaluateOrbit(b, kc.basis * c.partialPivLu().solve(Eigen::Vector2d(b.contacts[first].gap, at_t2)), {t2},
                       period, admissibility, {first, second});
}

std::vector<Orbit> TwoImpactOrbits(const AnalysisBasis& b, double period, const TwoImpactOptions& options, int first,
                                   int second) {
  std::vector<Orbit> out;
  for (double t2 : TwoImpactRoots(b, period, options, first, second)) {
    out.push_back(TwoImpactOrbitAt(b, t2, period, options, first, second));
  }
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
