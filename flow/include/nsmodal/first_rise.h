#pragma once
// The first time a sum of sinusoids (or of damped sinusoids, forced_flow.h)
// g rises to zero: the impact search of the
// exact integrator (g = x_c - d) and the release search while sticking
// (g = -a_c).
//
// Conservative advancement: from s, with g and its derivatives there and the
// bound L_k >= sup |g^(k)|, the Taylor polynomial
//   P(sigma) = g + g' sigma + ... + L_k sigma^k / k!      (k = 2, or 4 near tangency)
// bounds g(s + sigma) from above, so g stays below `level` up to P's first
// root: the step cannot pass a crossing, however short the excursion. At a
// transversal crossing the steps converge quadratically.
//
// Trigger rule (as Drake's witness functions): the search is armed once
// g < -2 tol; armed, it stops at g >= -tol; unarmed (starting inside the
// contact band |g| <= tol, right after an impact, a graze or a release) it
// stops only at g > max(tol, g(0) + tol), and steps with that level; a search
// that gets past that level without arming after leaving a point moving away
// (g' < 0) is taken back to the vertex of the quadratic bound at that point,
// where it arms wherever the bound proves a dip below -2 tol. A contact is never
// reported twice and never at s = 0. A transversal crossing
// (g' > sqrt(2 L2 tol)) found inside the band is finished by one Newton step.
//
// The sweep (SinusoidSweep, for sums of many sinusoids: an N-dof flight):
// where the search is armed and far below the level, it proves whole
// intervals [s, s + h] free of contact on a grid instead. With the phasors
// P_i(s) = (a_i - i b_i) e^{i w_i s}, g(s) = c + p s + sum Re P_i and
// g'(s) = p - sum w_i Im P_i, and a grid step is a rotation
// P_i <- P_i e^{i w_i h} (e^{i w_i h} computed once per step length): 6 N
// flops in single precision and no sin or cos, where a conservative step
// costs N of each. On an interval, g <= H3 + L4 h^4 / 384 (H3: the cubic
// Hermite interpolant of g, g' at its ends), g <= H5 + L6 h^6 / 46080 (H5:
// the quintic one of g, g', g'') and g <= max(g(s), g(s + h)) + L2 h^2 / 8,
// plus a bound on the round-off of the rotated phasors and of the sums; an
// interval is accepted when the least of those
// bound is below -tol (the armed search's stop level), so the sweep never
// passes a point where the search would stop. Where it cannot prove an
// interval (h halved down to its shortest), the conservative steps take over
// until they are past that interval. The contact itself, the band and the
// arming are the conservative search's alone.
#include <vector>

#include "nsmodal/flow.h"
#include "nsmodal/forced_flow.h"

namespace nsmodal {

struct FirstRiseResult {
  bool found = false;
  double s = 0.0;  // time of the crossing (found) or the horizon
  long steps = 0;        // conservative steps (N sin and cos each)
  long sweep_steps = 0;  // grid steps of the sweep (rotations)
  bool stalled = false;  // no progress at a degenerate tangency
};

// The grid's workspace for one set of frequencies (a model's modes): the
// rotations e^{i w_i h_k} for the step lengths h_k = h_0 / 2^k, each computed
// at its first use, and the phasors. Not thread-safe: one per simulation.
class SinusoidSweep {
 public:
  explicit SinusoidSweep(const Eigen::VectorXd& omega);

  // How far from s (armed, with d = g(s) and its first three derivatives,
  // exact) the grid proves g < level, up to the horizon.
  struct Reach {
    double s = 0.0;         // the end of the last interval proven (s: none)
    double blocked = 0.0;   // the length of the interval it could not prove (0: none)
    double declined = 0.0;  // level - g where it declined to step on (0: it did not)
    long steps = 0;
  };
  Reach Advance(const SinusoidSum& g, double s, const double d[4], double level, double horizon);
  // g.Derivatives(s, d), keeping the sin and cos of w_i s for an Advance
  // from s (the search's step before it: one evaluation of N of each saved).
  void Derivatives(const SinusoidSum& g, double s, double d[4]);

 private:
  const float* Rotation(int k);  // cos then sin of w_i h_k, 2n values

  Eigen::VectorXd omega_;
  double h0_ = 0.0;
  std::vector<double> h_;  // the step lengths h_0 / 2^k
  std::vector<std::vector<float>> rotation_;
  // Single precision (first_rise.cc says why, and how its round-off is bounded).
  std::vector<float> w_, re_, im_, next_re_, next_im_;  // w; phasors / l0 at s, at s + h
  std::vector<double> cos_, sin_;                      // cos, sin of w_i cached_at_ (if cached_)
  bool cached_ = false;
  double cached_at_ = 0.0;
};

FirstRiseResult FirstRise(const SinusoidSum& g, double horizon, double tol);
// With the sweep where armed (sweep.omega must be g's frequencies), and the
// conservative steps also bounded by the majorant of the quartic Taylor bound
// (|g''|, |g'''|, L4): for sums of many sinusoids, whose steps cost N sin and
// cos each (the exact integrator takes it from 8 modes on).
FirstRiseResult FirstRise(const SinusoidSum& g, double horizon, double tol, SinusoidSweep& sweep);
// The same search; the bounds hold for s >= 0 because every term decays.
FirstRiseResult FirstRise(const DampedSignal& g, double horizon, double tol);

}  // namespace nsmodal
