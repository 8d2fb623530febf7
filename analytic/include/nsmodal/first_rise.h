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
#include "nsmodal/flow.h"
#include "nsmodal/forced_flow.h"

namespace nsmodal {

struct FirstRiseResult {
  bool found = false;
  double s = 0.0;  // time of the crossing (found) or the horizon
  long steps = 0;
  bool stalled = false;  // no progress at a degenerate tangency
};

FirstRiseResult FirstRise(const SinusoidSum& g, double horizon, double tol);
// The same search; the bounds hold for s >= 0 because every term decays.
FirstRiseResult FirstRise(const DampedSignal& g, double horizon, double tol);

}  // namespace nsmodal
