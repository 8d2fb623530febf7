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

// The rigid-body part of a two-contact sequence (two_impact.h): the unit
// impulse directions' rigid components p1_r, p2_r and kappa with
// p2_r = kappa p1_r. Throws InputError naming "sequence" when a contact does
// not move the rigid-body modes or the two move them along different lines.
struct RigidPart {
  Eigen::VectorXd p1, p2;  // p1_r, p2_r
  double kappa = 0.0;
};
RigidPart RigidPartOf(const AnalysisBasis& b, int first, int second) {
  const std::string pair = "contacts " + std::to_string(first + 1) + " and " + std::to_string(second + 1);
  if (first == second) {
    throw InputError("sequence", pair + ": with a rigid-body mode (a free part, K semi-definite) one contact struck "
                                        "twice cannot send the free motion back; ask for two different contacts, "
                                        "e.g. 1,2");
  }
  const ModalContact &c1 = b.contacts[first], &c2 = b.contacts[second];
  RigidPart out;
  out.p1 = c1.r.head(b.rigid) / std::sqrt(c1.r_norm2);
  out.p2 = c2.r.head(b.rigid) / std::sqrt(c2.r_norm2);
  // p is a unit vector: 1e-12 is round-off of a component that is zero.
  for (const auto& [p, j] : {std::pair(&out.p1, first), std::pair(&out.p2, second)}) {
    if (!(p->norm() > 1e-12)) {
      throw InputError("sequence", pair + ": contact " + std::to_string(j + 1) +
                                       " does not move the rigid-body mode(s), so its impulse cannot send the " +
                                       "free motion back; no periodic orbit of this sequence has impacts");
    }
  }
  // Parallel: p2_r's part across p1_r below 1e-12 of it (the modal basis's
  // round-off is ~1e-15; a part of 1e-12 leaves the rigid velocity off by as
  // much after a period, the periodicity target).
  const double dot = out.p1.dot(out.p2);
  if (!((out.p2 - (dot / out.p1.squaredNorm()) * out.p1).norm() <= 1e-12 * out.p2.norm())) {
    throw InputError("sequence", pair + " push the rigid-body modes along different lines: the free motion " +
                                     "cannot return to its start; no periodic orbit of this sequence");
  }
  out.kappa = dot / out.p1.squaredNorm();
  return out;
}

}  // namespace

void CheckTwoImpactSequence(const AnalysisBasis& b, int first, int second) {
  if (b.rigid > 0) RigidPartOf(b, first, second);
}

SinusoidSum TwoImpactSignal(const AnalysisBasis& b, double period, int first, int second) {
  if (b.rigid > 0) {
    // F(t2) = |p2_r|^2 (2 t2 - T) / T + kappa sum_i rho_i (cot(w_i T/2) sin(w_i t2) - cos(w_i t2))
    // over the elastic modes (two_impact.h).
    const RigidPart rp = RigidPartOf(b, first, second);
    const ModalContact &c1 = b.contacts[first], &c2 = b.contacts[second];
    const double norms = std::sqrt(c1.r_norm2 * c2.r_norm2);
    const int ne = b.n - b.rigid;
    Eigen::VectorXd a(ne), c(ne);
    for (int k = 0; k < ne; ++k) {
      const int i = b.rigid + k;
      const double h = 0.5 * b.omega[i] * period;
      if (!(std::abs(std::sin(h)) > kSingularPeriod)) return {};
      const double rho = rp.kappa * c1.r[i] * c2.r[i] / norms;
      a[k] = -rho;
      c[k] = rho * std::cos(h) / std::sin(h);
    }
    const double p2 = rp.p2.squaredNorm();
    SinusoidSum f(-p2, std::move(a), std::move(c), b.omega.tail(ne));
    f.slope = 2.0 * p2 / period;
    f.UpdateBounds();
    return f;
  }
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
  if (p.omega.size() == 0 && p.slope == 0.0) return {};
  // Two contacts that share no mode (r1_i r2_i = 0 for every i: decoupled
  // parts) make P vanish for every t2: each wall's 1-impact orbit at any
  // phase, a continuum of orbits, not isolated roots.
  if (b.rigid == 0 && first != second && !(p.a.cwiseAbs().maxCoeff() > 0.5e-14)) {
    throw InputError("sequence", "contacts " + std::to_string(first + 1) + " and " + std::to_string(second + 1) +
                                     " move no common mode (decoupled parts): every t2 is a root, the orbits of "
                                     "the sequence are each contact's 1-impact orbits at any phase; ask for "
                                     "each contact's family instead");
  }
  const double half = 0.5 * period;
  const double min_width = 1e-12 * period;
  // P is odd about T/2 (two_impact.h): P(T/2 + x) = s x + sum_i A_i sin(w_i x),
  // A_i = b_i cos(w_i T/2) - a_i sin(w_i T/2). Its other roots are T/2 +- x
  // for the roots x in (0, T/2) of the even H(x) = P(T/2 + x) / x
  //   = s + sum_i A_i w_i sinc(w_i x).
  // Dividing by x takes out the root at T/2, which is triple where a pair of
  // asymmetric orbits is born from the symmetric one (a pitchfork): there the
  // cells that isolate P itself grow as 1 / sqrt(distance to it) (a sweep of
  // the impact damper's backbone met one at 4e-5 in P' and hit the work
  // limit), those that isolate H as its logarithm. The bounds:
  // |d^k/dx^k sinc(w x) w| <= w^(k+1) / (k + 1).
  const int terms = static_cast<int>(p.omega.size());
  Eigen::VectorXd amp(terms);
  double l1 = 0.0, l2 = 0.0;
  for (int i = 0; i < terms; ++i) {
    const double h = p.omega[i] * half;
    amp[i] = p.b[i] * std::cos(h) - p.a[i] * std::sin(h);
    const double w2 = p.omega[i] * p.omega[i];
    l1 += std::abs(amp[i]) * w2 / 2.0;
    l2 += std::abs(amp[i]) * w2 * p.omega[i] / 3.0;
  }
  const auto h_dh = [&p, &amp, terms](double x) {
    double h = p.slope, dh = 0.0;
    for (int i = 0; i < terms; ++i) {
      const double w = p.omega[i], u = w * x;
      double sinc, dsinc;  // sin(u) / u and its derivative in u
      if (std::abs(u) < 0.5) {
        // The series (the quotient (cos u - sinc) / u loses the digits of
        // cos u - sinc ~ -u^2 / 3: 3e-10 relative at u = 1e-3): with
        // s_k = (-1)^k u^(2k-1) / (2k+1)!, sinc = 1 + sum u s_k and
        // sinc' = sum 2k s_k; to k = 7, the first term left out is below
        // 1e-16 of each at |u| < 0.5.
        double s = -u / 6.0;
        sinc = 1.0;
        dsinc = 0.0;
        for (int k = 1; k <= 7; ++k) {
          sinc += u * s;
          dsinc += 2.0 * k * s;
          s *= -u * u / ((2.0 * k + 2.0) * (2.0 * k + 3.0));
        }
      } else {
        sinc = std::sin(u) / u;
        dsinc = (std::cos(u) - sinc) / u;
      }
      h += amp[i] * w * sinc;
      dh += amp[i] * w * w * dsinc;
    }
    return std::make_pair(h, dh);
  };
  // As CheckSegment (admissibility.cc): H has about w_max T / (2 pi) roots,
  // each isolated in ~40 halvings.
  const double w_max = terms > 0 ? p.omega.maxCoeff() : 0.0;
  const long max_cells = static_cast<long>(std::min(1e9, 1000.0 * (2.0 + w_max * period / M_PI)));
  bool complete = true;
  const std::vector<double> found = IsolateRoots(h_dh, l1, l2, 0.0, half, min_width, max_cells, &complete);
  if (!complete) {
    throw std::runtime_error("2-ipp roots at T = " + FormatValue(period) + ": the isolation of the roots of P(t2) hit its " +
                             "work limit of " + std::to_string(max_cells) + " cells");
  }
  std::vector<double> roots{half};  // exactly (eq. 26)
  for (double x : found) {
    // Coincident impacts (t2 at 0 or T) are 1-ipp orbits; T/2 is already in.
    if (x <= 1e-9 * period || x >= (0.5 - 1e-9) * period) continue;
    for (double t2 : {half - x, half + x}) {
      // T/2 - x loses the digits of a small t2 (x ~ T/2): one Newton step on
      // P itself restores them (a simple root; none at a tangency).
      double d[4];
      p.Derivatives(t2, d);
      const double step = d[0] / d[1];
      if (std::abs(step) <= 1e-9 * period && std::abs(p.Position(t2 - step)) < std::abs(d[0])) t2 -= step;
      // A bracket left at its minimum width is a tangency only if P vanishes there.
      if (std::abs(p.Position(t2)) <= options.kernel_tol * (p.bound[0] + std::abs(p.offset))) roots.push_back(t2);
    }
  }
  std::sort(roots.begin(), roots.end());
  return roots;
}

namespace {

// The potential orbit y0 = alpha k1 + beta k2 of a 2-dimensional kernel
// (k1, k2 of unit length) that meets NC2: the first contact's x_c(0) = d and
// the second's x_c(t2-) = d, evaluated. The two conditions coincide (rank 1)
// when the smaller singular value of their 2 x 2 matrix is at round-off level
// of the larger: then a line of y0 satisfies NC2 (degenerate, the bridge),
// and its minimum-norm member is taken.
Orbit OrbitInKernel(const AnalysisBasis& b, const Eigen::VectorXd& k1, const Eigen::VectorXd& k2, double t2,
                    double period, const TwoImpactOptions& options, int first, int second) {
  const ModalContact &c1 = b.contacts[first], &c2 = b.contacts[second];
  Eigen::VectorXd s1 = k1, s2 = k2;
  Flow(b, t2, s1);
  Flow(b, t2, s2);
  Eigen::Matrix2d c;
  c << ContactPosition(b, c1, k1), ContactPosition(b, c1, k2), ContactPosition(b, c2, s1), ContactPosition(b, c2, s2);
  const Eigen::Vector2d rhs(c1.gap, c2.gap);
  Eigen::JacobiSVD<Eigen::Matrix2d> csvd(c, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const bool degenerate = csvd.singularValues()[1] <= 1e-10 * csvd.singularValues()[0];
  Eigen::Vector2d coef;
  if (degenerate) {
    csvd.setThreshold(1e-10);
    coef = csvd.solve(rhs);
  } else {
    coef = c.partialPivLu().solve(rhs);
  }
  Orbit orbit = EvaluateOrbit(b, coef[0] * k1 + coef[1] * k2, {t2}, period, options.admissibility, {first, second});
  orbit.degenerate = degenerate;
  return orbit;
}

// TwoImpactOrbitAt with rigid-body modes (two_impact.h): y0 = alpha K1 + gamma E,
// K1 = 2 X_e (S_e(T - t2) p2 - kappa p1) in the elastic modes and the rigid
// velocity 2 (T - t2) / T p2_r; E the unit shift along p1_r (the shifts
// across it move no gap: the minimum-norm orbit leaves them at 0).
Orbit RigidTwoImpactOrbitAt(const AnalysisBasis& b, double t2, double period, const TwoImpactOptions& options,
                            int first, int second) {
  const int n = b.n;
  const RigidPart rp = RigidPartOf(b, first, second);
  const ModalContact &c1 = b.contacts[first], &c2 = b.contacts[second];
  Eigen::VectorXd k1 = Eigen::VectorXd::Zero(2 * n), e = Eigen::VectorXd::Zero(2 * n);
  const double norm1 = std::sqrt(c1.r_norm2), norm2 = std::sqrt(c2.r_norm2);
  for (int i = b.rigid; i < n; ++i) {
    const double p1 = c1.r[i] / norm1, p2 = c2.r[i] / norm2;
    const double k = 0.5 * std::cos(0.5 * b.omega[i] * period) / std::sin(0.5 * b.omega[i] * period);
    const double c = std::cos(b.omega[i] * (period - t2)), s = std::sin(b.omega[i] * (period - t2));
    k1[i] = 2.0 * (p2 * (-0.5 * s - k * c) + rp.kappa * p1 * k);
    k1[n + i] = 2.0 * (p2 * (k * s - 0.5 * c) + rp.kappa * p1 * 0.5);
  }
  k1.segment(n, b.rigid) = (2.0 * (period - t2) / period) * rp.p2;
  // Unit length, as E: K1 grows as cot(w T / 2) near a multiple of a linear
  // period, and the rank test below compares the two columns' scales.
  k1.normalize();
  e.head(b.rigid) = rp.p1.normalized();
  return OrbitInKernel(b, k1, e, t2, period, options, first, second);  // (E is a fixed point of every flight)
}

}  // namespace

Orbit TwoImpactOrbitAt(const AnalysisBasis& b, double t2, double period, const TwoImpactOptions& options, int first,
                       int second) {
  if (b.rigid > 0) return RigidTwoImpactOrbitAt(b, t2, period, options, first, second);
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
  Orbit orbit = OrbitInKernel(b, k1, k2, t2, period, options, first, second);
  const bool degenerate = orbit.degenerate;
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
  b.RequireElastic("the 2-impact kernel from the SVD");
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
  // (With a rigid-body mode A_2 always has the shift in its kernel: this
  // would be ~0 at every t2.)
  b.RequireElastic("the 2-impact kernel residual sigma_min(A_2)");
  return SmallestSingularValue(b, t2, period);
}

std::vector<BranchPoint> TwoImpactBranch(const AnalysisBasis& b, double t2, double period, const BranchOptions& options) {
  b.RequireElastic("the continuation of the 2-impact root curve");
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
