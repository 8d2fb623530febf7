#include "nsmodal/first_rise.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "nsmodal/simd.h"

namespace nsmodal {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
// The sweep's step lengths h_k = h_0 / 2^k, k <= kLevels - 1, with
// h_0 = 64 / w_max (long steps pay where the slow modes carry the signal)
// down to 2^-9 / w_max: near a crossing the grid steps, a tenth of a
// conservative step's cost at N = 1,000, take the sweep closer to it.
constexpr int kLevels = 16;
constexpr double kLongestStep = 64.0;
// The phasors are computed afresh (in double precision, then rounded) after
// this many rotations: their round-off grows by about 6 float epsilons a
// rotation (after 256, 1.8e-4 of the sum of the amplitudes; the sums of
// 1,000 terms allow as much).
constexpr int kResync = 256;
constexpr double kFloatEps = std::numeric_limits<float>::epsilon();

// One grid step: the phasors (re, im) rotated by (c, sn) into (nre, nim);
// returns sum nre, sum w nim and sum w^2 nre (g, -g', -g'' over l0). In single
// precision: the arrays of 1,000 modes then fit in the first-level cache, and
// a vector holds 8 modes (0.7 -> 0.3 us a step at N = 1,000); the sweep's
// margin counts the round-off (SinusoidSweep::Advance).
struct Sums {
  float x, wy, w2x;
};
[[gnu::always_inline]] inline Sums RotateBody(int n, const float* w, const float* c, const float* sn, const float* re,
                                              const float* im, float* nre, float* nim) {
  float sum_x = 0.0f, sum_wy = 0.0f, sum_w2x = 0.0f;
#pragma omp simd reduction(+ : sum_x, sum_wy, sum_w2x)
  for (int i = 0; i < n; ++i) {
    const float x = re[i] * c[i] - im[i] * sn[i];
    const float y = re[i] * sn[i] + im[i] * c[i];
    nre[i] = x;
    nim[i] = y;
    sum_x += x;
    sum_wy += w[i] * y;
    sum_w2x += w[i] * w[i] * x;
  }
  return {sum_x, sum_wy, sum_w2x};
}
Sums RotatePlain(int n, const float* w, const float* c, const float* sn, const float* re, const float* im, float* nre,
                 float* nim) {
  return RotateBody(n, w, c, sn, re, im, nre, nim);
}
#if NSMODAL_X86
NSMODAL_AVX2 Sums RotateAvx2(int n, const float* w, const float* c, const float* sn, const float* re, const float* im,
                             float* nre, float* nim) {
  return RotateBody(n, w, c, sn, re, im, nre, nim);
}
#endif
Sums Rotate(int n, const float* w, const float* c, const float* sn, const float* re, const float* im, float* nre,
            float* nim) {
#if NSMODAL_X86
  if (internal::HasAvx2()) return RotateAvx2(n, w, c, sn, re, im, nre, nim);
#endif
  return RotatePlain(n, w, c, sn, re, im, nre, nim);
}

// An upper bound of the quintic Hermite interpolant of the values p, slopes
// d and second derivatives e at the ends of [0, h]: the largest of its
// Bernstein coefficients on [0, 1] after one subdivision at 1/2 (the curve
// lies in their convex hull).
double QuinticBound(double p0, double d0, double e0, double p1, double d1, double e1, double h) {
  const double m0 = d0 * h, m1 = d1 * h, c0 = e0 * h * h, c1 = e1 * h * h;
  double b[6] = {p0, p0 + m0 / 5.0, p0 + 0.4 * m0 + c0 / 20.0, p1 - 0.4 * m1 + c1 / 20.0, p1 - m1 / 5.0, p1};
  double best = std::max(p0, p1);
  // de Casteljau at 1/2: the left half's points are the first entries of
  // each level, the right half's the last.
  for (int level = 5; level > 0; --level) {
    for (int i = 0; i < level; ++i) b[i] = 0.5 * (b[i] + b[i + 1]);
    best = std::max({best, b[0], b[level - 1]});
  }
  return best;
}

// The maximum over [0, h] of the cubic Hermite interpolant of the values p0,
// p1 and slopes d0, d1 at the ends.
double HermiteMax(double p0, double d0, double p1, double d1, double h) {
  const double m0 = d0 * h, m1 = d1 * h;
  const double c1 = m0, c2 = -3.0 * p0 - 2.0 * m0 + 3.0 * p1 - m1, c3 = 2.0 * p0 + m0 - 2.0 * p1 + m1;
  double best = std::max(p0, p1);
  auto at = [&](double x) {
    if (x > 0.0 && x < 1.0) best = std::max(best, p0 + x * (c1 + x * (c2 + x * c3)));
  };
  // H'(x) / h = c1 + 2 c2 x + 3 c3 x^2
  const double qa = 3.0 * c3, qb = 2.0 * c2, qc = c1;
  if (qa == 0.0) {
    if (qb != 0.0) at(-qc / qb);
  } else {
    const double disc = qb * qb - 4.0 * qa * qc;
    if (disc >= 0.0) {
      const double q = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
      if (q != 0.0) {
        at(q / qa);
        at(qc / q);
      } else {
        at(0.0);  // qb = qc = 0: the only critical point is x = 0
      }
    }
  }
  return best;
}

// A step no longer than the smallest positive real root of
// c0 + c1 s + c2 s^2 + c3 s^3 + c4 s^4 (c0 < 0, c4 > 0): the smallest positive
// real part among the roots within 45 degrees of the real axis. A double root
// (the bound touching zero at a tangency) comes out of the eigenvalue solver
// as a complex pair ~sqrt(eps) off the axis; it must not be skipped, and
// taking a real part of a complex root is only ever shorter, so safe.
// The polynomial is first scaled to s = s0 t with s0 = (-c0 / c4)^(1/4), so
// that its end coefficients are -1 and 1: with the fast modes of a fine mesh
// c4 / |c0| reaches 1e40 and the unscaled companion matrix loses the real
// root (a bar of 200 elements stepped over its contact). No root found: 0
// (the caller keeps its quadratic step).
double FirstPositiveRootQuartic(const double c[5]) {
  const double s0 = std::pow(-c[0] / c[4], 0.25);
  if (!(s0 > 0.0) || !std::isfinite(s0)) return 0.0;
  double scaled[5];
  double pk = 1.0;
  for (int i = 0; i < 5; ++i, pk *= s0) scaled[i] = c[i] * pk / -c[0];
  Eigen::Matrix4d comp = Eigen::Matrix4d::Zero();
  for (int i = 0; i < 3; ++i) comp(i + 1, i) = 1.0;
  for (int i = 0; i < 4; ++i) comp(i, 3) = -scaled[i] / scaled[4];
  const Eigen::Vector4cd roots = comp.eigenvalues();
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i) {
    const double re = roots[i].real();
    if (re > 0.0 && std::abs(roots[i].imag()) <= re) best = std::min(best, re);
  }
  return std::isfinite(best) ? best * s0 : 0.0;
}

// A step no longer than the first positive root of the majorant
//   M(s) = g0 + g1 s + |g2| s^2 / 2 + |g3| s^3 / 6 + L4 s^4 / 24     (g0 < 0)
// of the quartic Taylor bound (so of g) for s >= 0. Its coefficients change
// sign once, so it has one positive root r, with M < 0 exactly on [0, r);
// it is convex for s > 0, so Newton's iteration from the right of r
// decreases monotonically to r. Where the actual curvature is far below its
// bound L2 (a sum of many sinusoids: |g''| ~ L2 / sqrt(N)), this step is
// longer than the quadratic one, and costs a few polynomial evaluations
// instead of the quartic's eigenvalues. 0 when not found (the caller keeps
// its quadratic step).
double MajorantStep(double g0, const double d[4], double l4) {
  const double c1 = d[1], c2 = 0.5 * std::abs(d[2]), c3 = std::abs(d[3]) / 6.0, c4 = l4 / 24.0;
  auto m = [&](double x) { return g0 + x * (c1 + x * (c2 + x * (c3 + x * c4))); };
  auto dm = [&](double x) { return c1 + x * (2.0 * c2 + x * (3.0 * c3 + x * 4.0 * c4)); };
  // A start right of r: with g1 > 0, M(-g0 / g1) >= g0 + g1 (-g0 / g1) = 0;
  // otherwise the quartic term alone outgrows the rest somewhere.
  double x = c1 > 0.0 ? -g0 / c1 : std::sqrt(std::sqrt(-g0 / c4));
  for (int i = 0; i < 64 && !(m(x) >= 0.0); ++i) x *= 2.0;
  if (!(m(x) >= 0.0) || !std::isfinite(x)) return 0.0;
  for (int i = 0; i < 50; ++i) {
    const double next = x - m(x) / dm(x);
    if (!(next < x)) break;  // converged (or round-off): x is right of r
    const bool done = x - next <= 1e-12 * x;
    x = next;
    if (done) break;
  }
  const double step = x * (1.0 - 1e-9);
  return m(step) < 0.0 ? step : 0.0;
}

double MaxRate(const SinusoidSum& g) { return g.omega.size() > 0 ? g.omega.maxCoeff() : 1.0; }
double MaxRate(const DampedSignal& g) { return g.MaxRate(); }

template <typename Signal>
FirstRiseResult Search(const Signal& g, double horizon, double tol, SinusoidSweep* sweep) {
  FirstRiseResult out;
  const double l2 = g.bound[2], l4 = g.bound[4];
  const double w_max = MaxRate(g);
  double s = 0.0;
  double d[4];
  // With the sweep, through it: it keeps the sin and cos for its own start.
  auto derivatives = [&](double at) {
    if constexpr (std::is_same_v<Signal, SinusoidSum>) {
      if (sweep != nullptr) return sweep->Derivatives(g, at, d);
    }
    g.Derivatives(at, d);
  };
  derivatives(0.0);
  bool armed = d[0] < -2.0 * tol;
  // Unarmed, a contact is a rise tol above the start (or above the band), so
  // a start already past +tol (a graze's slow excursion) cannot fire at s = 0.
  const double rise = std::max(tol, d[0] + tol);
  int no_progress = 0;
  // The last point the search left unarmed while moving away (g' < 0), and
  // the slope there.
  bool away = false, backtracked = false;
  double away_s = 0.0, away_slope = 0.0;
  // The sweep is next tried from sweep_from on, where g <= sweep_below.
  double sweep_from = 0.0, sweep_below = std::numeric_limits<double>::infinity();
  while (true) {
    ++out.steps;
    if (!armed && d[0] > rise && away && !backtracked) {
      // Back on the rise without ever arming: with a tight bound (a
      // constant acceleration, as under a preload) one step can cross the
      // whole dip, and the unarmed rule would report the contact at +tol
      // without the Newton finish, a band-width past the wall (an error that
      // accumulates over a Zeno sequence). Step back to the vertex of the
      // quadratic bound at the last point left moving away instead: g there is at most
      // g - g'^2 / (2 L2), below -2 tol wherever the dip is provable, so the
      // search arms there. (Searches that armed on their own are unchanged.)
      backtracked = true;
      s = away_s - away_slope / l2;
      derivatives(s);
      if (d[0] < -2.0 * tol) armed = true;
      continue;
    }
    if (armed ? d[0] >= -tol : d[0] > rise) {
      out.found = true;
      out.s = s;
      // A transversal crossing within the band: one Newton step puts it at
      // machine precision (its error is ~ L2 (g/g')^2 / g'). Only when the
      // slope beats the curvature bound, g' > sqrt(2 L2 tol): then the step
      // is at most sqrt(tol / (2 L2)) and cannot jump over a slow tangency
      // (a slower crossing is a graze to the contact logic anyway).
      if (armed && d[1] * d[1] > 2.0 * l2 * tol && -d[0] < d[1] * horizon) {
        out.s = std::min(horizon, s - d[0] / d[1]);
      }
      return out;
    }
    if constexpr (std::is_same_v<Signal, SinusoidSum>) {
      if (sweep != nullptr && armed && s >= sweep_from && d[0] <= sweep_below) {
        const SinusoidSweep::Reach reach = sweep->Advance(g, s, d, -tol, horizon);
        out.sweep_steps += reach.steps;
        // Past an interval the grid could not prove, the conservative steps
        // go on until they are beyond it. Where it declined to step (a
        // crossing or a tangency near: the conservative steps converge there
        // in a few), it is asked again only once g has fallen back 4 times
        // further from the level (each restart costs a conservative step's
        // sin and cos).
        sweep_from = reach.s + reach.blocked;
        sweep_below = reach.declined > 0.0 ? -tol - 4.0 * reach.declined : std::numeric_limits<double>::infinity();
        if (reach.s > s) {
          s = reach.s;
          if (s >= horizon) {
            out.s = horizon;
            return out;
          }
          derivatives(s);
          continue;
        }
      }
    }
    const double level = armed ? 0.0 : rise;
    const double g0 = d[0] - level;  // < 0
    double sigma;
    if (l2 <= 0.0) {
      // An affine signal (a constant, or a rigid-body drift): exactly linear,
      // so step to tol past the level (inside the contact band) or forever.
      sigma = d[1] > 0.0 ? (tol - g0) / d[1] : std::numeric_limits<double>::infinity();
    } else {
      // The first root of g0 + g' sigma + L2 sigma^2 / 2, in the form without
      // cancellation: with g' > 0 and L2 |g0| << g'^2 (a nearly affine
      // signal: a drift whose vibration is round-off) (-g' + sqrt(.)) / L2
      // is 0 to round-off, and the search stalled short of a contact.
      const double root = std::sqrt(d[1] * d[1] - 2.0 * l2 * g0);
      sigma = d[1] > 0.0 ? -2.0 * g0 / (d[1] + root) : (root - d[1]) / l2;
      // (With a sweep only: a signal of many terms, where a step's N sin and
      // cos outweigh the majorant's polynomial evaluations; on the paper's
      // 2 modes they did not.)
      if (sweep != nullptr && l4 > 0.0 && std::abs(d[2]) < 0.5 * l2) sigma = std::max(sigma, MajorantStep(g0, d, l4));
      if (sigma * w_max < 1e-3 && l4 > 0.0 && d[1] * d[1] < -2.0 * l2 * g0) {
        // Near a tangency (the slope does not dominate the curvature bound) the
        // quadratic bound is too pessimistic: the quartic one uses the actual
        // curvature and third derivative. Near a transversal crossing the
        // quadratic step is already Newton-like and converges quadratically.
        const double c[5] = {g0, d[1], 0.5 * d[2], d[3] / 6.0, l4 / 24.0};
        sigma = std::max(sigma, FirstPositiveRootQuartic(c));
      }
    }
    if (!(sigma > 1e-15 * std::max(1.0, s))) {
      if (++no_progress > 1000) {
        out.stalled = true;
        out.s = s;
        return out;
      }
      sigma = 1e-15 * std::max(1.0, s);
    } else {
      no_progress = 0;
    }
    if (!armed && d[1] < 0.0 && l2 > 0.0) {
      away = true;
      away_s = s;
      away_slope = d[1];
    }
    s += sigma;
    if (s >= horizon) {
      out.s = horizon;
      return out;
    }
    derivatives(s);
    if (!armed && d[0] < -2.0 * tol) armed = true;
  }
}

}  // namespace

SinusoidSweep::SinusoidSweep(const Eigen::VectorXd& omega)
    : omega_(omega),
      rotation_(kLevels),
      w_(omega.data(), omega.data() + omega.size()),
      re_(omega.size()),
      im_(omega.size()),
      next_re_(omega.size()),
      next_im_(omega.size()),
      cos_(omega.size()),
      sin_(omega.size()) {
  const double w_max = omega.size() > 0 ? omega.maxCoeff() : 0.0;
  h0_ = w_max > 0.0 ? kLongestStep / w_max : 0.0;
  for (int k = 0; k < kLevels; ++k) h_.push_back(std::ldexp(h0_, -k));
}

const float* SinusoidSweep::Rotation(int k) {
  std::vector<float>& r = rotation_[k];
  if (r.empty()) {
    const int n = static_cast<int>(omega_.size());
    std::vector<double> c(n), sn(n);
    internal::CosSin(omega_.data(), h_[k], n, c.data(), sn.data());
    r.resize(2 * n);
    for (int i = 0; i < n; ++i) {
      r[i] = static_cast<float>(c[i]);
      r[n + i] = static_cast<float>(sn[i]);
    }
  }
  return r.data();
}

void SinusoidSweep::Derivatives(const SinusoidSum& g, double s, double d[4]) {
  if (g.omega.size() != omega_.size()) return g.Derivatives(s, d);
  internal::CosSin(omega_.data(), s, static_cast<int>(omega_.size()), cos_.data(), sin_.data());
  cached_ = true;
  cached_at_ = s;
  g.Derivatives(s, cos_.data(), sin_.data(), d);
}

SinusoidSweep::Reach SinusoidSweep::Advance(const SinusoidSum& g, double s, const double d[4], double level,
                                            double horizon) {
  const double g0 = d[0], g1 = d[1];
  Reach out;
  out.s = s;
  const int n = static_cast<int>(omega_.size());
  const double l0 = g.bound[0], l1 = g.bound[1], l2 = g.bound[2], l4 = g.bound[4], l6 = g.bound[6];
  if (h0_ <= 0.0 || g.omega.size() != n || !(l0 > 0.0) || !(g0 < level)) return out;
  // The phasors are kept divided by l0 = sum of the amplitudes (so in [-1, 1],
  // far from float's overflow and underflow). Their round-off, in units of
  // l0 (first order in the float epsilon u, with u at least the unit
  // roundoff): u from rounding the exact phasors, then at most 6 u a rotation
  // (4 operations, and the rounded cos and sin); the sums of n terms add
  // n u, the float frequencies u (times l1). Below, with m rotations since
  // the last fresh start, ulps = (6 m + n + 6) u: |error of g| <= ulps l0
  // and |error of g'| <= ulps l1; subnormal round-off (2^-149 an operation,
  // a few per term) is covered by the n * FLT_MIN.
  struct Margins {
    double cubic, quintic;
  };
  auto margin_of = [&](int m, double h, double t) {
    const double ulps = (6.0 * m + n + 6.0) * kFloatEps, tiny = n * std::numeric_limits<float>::min();
    const double value = (ulps + tiny) * l0 + 4.0 * kEps * (std::abs(g.offset) + std::abs(g.slope * t));
    const double slope = (ulps + tiny) * l1, curvature = (ulps + tiny) * l2;
    // The interpolants' weights: the cubic's at most 1 on the values and
    // 4/27 h on each slope; the quintic's Bernstein coefficients at most 1 on
    // the values, 2/5 h on the slopes, h^2 / 20 on the second derivatives.
    return Margins{value + 0.3 * h * slope, value + 0.4 * h * slope + 0.05 * h * h * curvature};
  };
  // The longest step whose error term (the cubic's or the quintic's) takes
  // at most half the distance to the level, and over which the current slope
  // would not reach it: the level k to try first (kLevels when even the
  // shortest would not do), searched from two levels above `from` down,
  // with no root taken (a third of the sweep's time went to that overhead).
  // (Measured on the 1,000-mass chain: 99% of the steps so chosen are
  // accepted, within 0.13 level of the longest step that would have been;
  // limiting the slope's rise to half the distance took 20% more steps.)
  auto first_level = [&](double p, double slope, double t, int m, int from) {
    for (int k = std::max(0, from - 2); k < kLevels; ++k) {
      const double h = h_[k], h2 = h * h;
      const double room = level - p - margin_of(m + 1, h, t).quintic;
      if (!(room > 0.0) || slope * h > room) continue;
      if ((l4 > 0.0 && l4 * h2 * h2 <= 192.0 * room) || (l6 > 0.0 && l6 * h2 * h2 * h2 <= 23040.0 * room) ||
          (l2 > 0.0 && l2 * h2 <= 4.0 * room) || (l2 <= 0.0 && l4 <= 0.0 && l6 <= 0.0)) {
        return k;
      }
    }
    return kLevels;
  };
  // Far enough below the level, the conservative step (the first root of
  // the quadratic bound) is longer than the longest grid step: the sweep
  // leaves it those stretches (a wall never reached would otherwise be swept
  // to the horizon in steps of h_0).
  auto conservative_longer = [&](double p, double slope) {
    if (!(l2 > 0.0)) return true;
    const double room = level - p;
    return (std::sqrt(slope * slope + 2.0 * l2 * room) - slope) / l2 > h0_;
  };
  if (conservative_longer(g0, g1)) return out;
  int k = first_level(g0, g1, s, 0, 0);
  if (k >= kLevels) {
    out.declined = level - g0;
    return out;
  }

  int rotations = 0;
  auto start_at = [&](double t) {
    if (!(cached_ && t == cached_at_)) internal::CosSin(omega_.data(), t, n, cos_.data(), sin_.data());
    cached_ = false;
    const double inv = 1.0 / l0;
    for (int i = 0; i < n; ++i) {
      re_[i] = static_cast<float>(inv * (g.a[i] * cos_[i] + g.b[i] * sin_[i]));
      im_[i] = static_cast<float>(inv * (g.a[i] * sin_[i] - g.b[i] * cos_[i]));
    }
    rotations = 0;
  };
  start_at(s);
  double p0 = g0, d0 = g1, e0 = d[2];
  while (out.s < horizon) {
    const double h = h_[k];
    const float* rot = Rotation(k);
    const Sums sums = Rotate(n, w_.data(), rot, rot + n, re_.data(), im_.data(), next_re_.data(), next_im_.data());
    ++out.steps;
    const double t1 = out.s + h;
    if (!(t1 > out.s)) break;  // h below the resolution of s: the conservative search says it stalled
    const double p1 = g.offset + g.slope * t1 + l0 * static_cast<double>(sums.x);
    const double d1 = g.slope - l0 * static_cast<double>(sums.wy);
    const double e1 = -l0 * static_cast<double>(sums.w2x);
    const double h2 = h * h;
    const Margins margin = margin_of(rotations + 1, h, t1);
    auto above = [&](double b, double m) { return b + 8.0 * kEps * std::abs(b) + m; };
    // The quintic bound first (no square root); the cubic only if it fails.
    auto proven = [&] {
      const double quintic = QuinticBound(p0, d0, e0, p1, d1, e1, h) + l6 * h2 * h2 * h2 / 46080.0;
      if (above(quintic, margin.quintic) < level) return true;
      const double cubic =
          std::min(HermiteMax(p0, d0, p1, d1, h) + l4 * h2 * h2 / 384.0, std::max(p0, p1) + l2 * h2 / 8.0);
      return above(cubic, margin.cubic) < level;
    };
    if (proven()) {
      std::swap(re_, next_re_);
      std::swap(im_, next_im_);
      ++rotations;
      out.s = t1;
      p0 = p1;
      d0 = d1;
      e0 = e1;
      if (rotations >= kResync && out.s < horizon) {
        // Afresh, and the left end's values with them (the margin counts
        // rotations since this start for both ends of a step).
        start_at(out.s);
        double exact[4];
        g.Derivatives(out.s, cos_.data(), sin_.data(), exact);
        p0 = exact[0];
        d0 = exact[1];
        e0 = exact[2];
      }
      if (conservative_longer(p0, d0)) break;
      k = first_level(p0, d0, out.s, rotations, k);
      if (k >= kLevels) {
        out.declined = level - p0;
        break;
      }
    } else if (k + 1 < kLevels) {
      ++k;
    } else {
      out.blocked = h;
      break;
    }
  }
  out.s = std::min(out.s, horizon);
  return out;
}

FirstRiseResult FirstRise(const SinusoidSum& g, double horizon, double tol) {
  return Search(g, horizon, tol, nullptr);
}
FirstRiseResult FirstRise(const SinusoidSum& g, double horizon, double tol, SinusoidSweep& sweep) {
  return Search(g, horizon, tol, &sweep);
}
FirstRiseResult FirstRise(const DampedSignal& g, double horizon, double tol) {
  return Search(g, horizon, tol, static_cast<SinusoidSweep*>(nullptr));
}

}  // namespace nsmodal
