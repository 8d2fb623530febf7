#include "nsmodal/first_rise.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

namespace nsmodal {
namespace {

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

double MaxRate(const SinusoidSum& g) { return g.omega.size() > 0 ? g.omega.maxCoeff() : 1.0; }
double MaxRate(const DampedSignal& g) { return g.MaxRate(); }

template <typename Signal>
FirstRiseResult Search(const Signal& g, double horizon, double tol) {
  FirstRiseResult out;
  const double l2 = g.bound[2], l4 = g.bound[4];
  const double w_max = MaxRate(g);
  double s = 0.0;
  double d[4];
  g.Derivatives(0.0, d);
  bool armed = d[0] < -2.0 * tol;
  // Unarmed, a contact is a rise tol above the start (or above the band), so
  // a start already past +tol (a graze's slow excursion) cannot fire at s = 0.
  const double rise = std::max(tol, d[0] + tol);
  int no_progress = 0;
  // The last point the search left unarmed while moving away (g' < 0), and
  // the slope there.
  bool away = false, backtracked = false;
  double away_s = 0.0, away_slope = 0.0;
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
      g.Derivatives(s, d);
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
    g.Derivatives(s, d);
    if (!armed && d[0] < -2.0 * tol) armed = true;
  }
}

}  // namespace

FirstRiseResult FirstRise(const SinusoidSum& g, double horizon, double tol) { return Search(g, horizon, tol); }
FirstRiseResult FirstRise(const DampedSignal& g, double horizon, double tol) { return Search(g, horizon, tol); }

}  // namespace nsmodal
