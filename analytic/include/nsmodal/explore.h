#pragma once
// Exploratory search for m >= 3 impacts per period (paper section 2.3), on
// coarse grids of the impact times, to test the paper's conjectures:
//   odd m:  dim ker A_m = 1 everywhere (Q_m is orthogonal with det -1);
//   even m: dim ker A_m = 2 on the roots of det A_m;
//   potential solutions exist only as degenerate counterparts of fewer impacts
//   (a lower-m orbit repeated, or a 1-ipp orbit with grazing contacts).
// The search minimises phi = sigma_k(A_m) (k = 2 for even m, 0 for odd m) +
// the NC2 least-squares misfit in the span of the k smallest singular vectors,
// from the best grid points, with GSL's Nelder-Mead simplex.
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "nsmodal/field_names.h"
#include "nsmodal/modal_basis.h"
#include "nsmodal/orbit.h"

namespace nsmodal {

struct ExploreOptions {
  int impacts = 3;
  // The contact of each impact (0-based, `impacts` entries, issue 24): A_m
  // with each impact's own reflection, NC2 on each impact's own wall; empty:
  // every impact on contact 1. A finding is the same orbit as another only
  // by a rotation that maps the sequence onto itself, and a lower-m orbit
  // repeated only when the sequence repeats with it.
  std::vector<int> sequence;
  int grid = 24;            // grid nodes per impact-time axis on (0, T)
  int starts_per_period = 6;  // best grid points polished per period
  // A polished point is a potential solution when phi is below this; phi
  // measures defects of O(1) quantities, polished to ~1e-12 where a root exists.
  double potential_tol = 1e-8;
  int threads = 0;  // periods searched in parallel (0: all cores)
  std::function<void(long done, long count)> progress;
};

// Whether two consecutive impacts of an orbit (times = t2..tm, t1 = 0, and
// tm to T + 0) fall at one instant, to 1e-6 T, on one contact
// (same_contact: they cancel, N^2 = I) or on two different ones (a
// simultaneous impact). An empty sequence: every impact on contact 1.
bool CoincidentImpacts(const std::vector<double>& times, double period, int impacts, const std::vector<int>& sequence,
                       bool same_contact);

struct ExploreFinding {
  Orbit orbit;
  // "repeated-lower-m" (a lower-m orbit repeated, or two impacts of one
  // contact at one instant, which cancel), "simultaneous-impacts" (two
  // different contacts struck at one instant: a corner of the gaps, one
  // impact instant fewer), "grazing-contact" (an impact at zero velocity:
  // fewer true impacts), or "new".
  std::string kind;
  int kernel_dimension = 0;
  double grazing_ratio = 0.0;  // min |v_c-| / max |v_c-| over the impacts
};

struct ExploreReport {
  int impacts = 0;
  long samples = 0;
  std::map<int, long> kernel_dimension_histogram;  // over grid samples (odd m) or findings (even m)
  std::vector<ExploreFinding> findings;            // distinct potential orbits (cyclic shifts merged)
  double best_phi_new = 0.0;                       // smallest phi away from repeated lower-m orbits
  // Findings of one kind ("new", "grazing-contact", "simultaneous-impacts", "repeated-lower-m").
  long Count(const std::string& kind, bool admissible_only = false) const;
};

// Throws InputError naming "impacts" (3 to 6), "grid" (4 to 200) or
// "sequence" (not `impacts` entries, or a contact that does not exist).
ExploreReport ExploreImpacts(const AnalysisBasis& b, const std::vector<double>& periods, const ExploreOptions& options);

// Continuation in T of a family of potential orbits with an odd number m of
// impacts (dim ker A_m = 1, explore.h), on the start's sequence: with y the
// kernel vector and c_i its n_{j_i} . x at the impacts, NC2 is
// (c_i / d_{j_i}) / (c_0 / d_{j_0}) = 1 for i = 1..m-1, m - 1 equations in
// the m - 1 impact times t_2..t_m. From `start` the period steps by `step`
// towards `to`; each point is predicted by the secant of the last two and
// corrected by Newton (finite-difference Jacobian, at most 30 iterations,
// converged at max |c_i / c_0 - 1| <= 1e-13); a point that does not converge,
// or whose correction is more than ten times the step's prediction (or the
// step: it landed on another branch, as past a fold where the family turns
// back in T), is retried at half the step, at most 30 times and while the
// step is at least 1e-7 T. It stops at `to`, or after
// the first point that is not potential (a flight or an impact velocity
// changing sign: the family has left the orbits with m impacts). Where
// admissibility changes for the first time between two points, the change
// is located by bisection in T to 1e-12 T.
struct FamilyOptions {
  double step = 0.01;
  long max_points = 100000;  // a bound on the work; reported when hit
};
struct Family {
  std::vector<Orbit> orbits;  // in the order followed, start first
  // The first period from `start` towards `to` where admissibility changes
  // (NaN: none met), and the orbit just on start's side of it.
  double admissibility_change = 0.0;
  Orbit at_change;
  std::string stop;  // why the continuation ended ("reached T = ...", or what failed)
};
// Throws InputError naming "impacts" (odd, 3 to 5: the start's), "period" (to
// outside what the basis honours) or "step" (not positive and finite).
Family FollowOddImpactFamily(const AnalysisBasis& b, const Orbit& start, double to, const FamilyOptions& options = {});

// The family followed both ways from `start`, down to `from` and up to `to`,
// and the stretch of it around start between the first admissibility changes
// (where there is none, the period the continuation reached on that side).
struct FamilyStretch {
  Family down, up;
  double from = 0.0, to = 0.0;
  std::vector<Orbit> Ascending() const;  // every orbit followed, ascending T, start once
};
FamilyStretch FollowOddImpactFamilyBothWays(const AnalysisBasis& b, const Orbit& start, double from, double to,
                                            const FamilyOptions& options = {});

// explore --follow: the family of each admissible new orbit of an
// exploration (odd m), followed both ways over [from, to] and summed up over
// its admissible orbits (the start once). A family met again from another
// of its orbits (the same stretch to 1e-9 T) is given once, at the first.
struct FamilySummary {
  Orbit start;                        // the finding it was followed from
  double from = 0.0, to = 0.0;        // the stretch (FamilyStretch::from, to)
  // Why it ended on that side (Family::stop), when no admissibility change ended it there.
  std::optional<std::string> lower_end, upper_end;
  long points = 0;                    // admissible orbits
  double energy_min = INFINITY, energy_max = 0.0;
  double multiplier_min = INFINITY, multiplier_max = 0.0;  // largest |Floquet multiplier|, where defined
};
// Throws InputError naming "follow" (as `names` says: the CLI's --follow)
// when the report's m is even or [from, to] leaves the periods the basis
// honours, before any work; as FollowOddImpactFamily otherwise.
void CheckFamilyRange(const AnalysisBasis& b, int impacts, double from, double to, const FieldNames& names = FieldNames());
std::vector<FamilySummary> FollowNewFamilies(const AnalysisBasis& b, const ExploreReport& report, double from,
                                             double to, const FamilyOptions& options = {});

}  // namespace nsmodal
