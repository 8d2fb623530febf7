#pragma once
// Validation of analytic periodic orbits by simulation over long horizons.
//
// Each orbit (its post-impact state z0 from the kernel of A_m) is simulated
// from the middle of its first flight, z_mid = S(tau_1 / 2) z0, so that the
// comparison points k T never coincide with an impact. Per orbit and
// integrator:
//   periodicity   deviation_k = |z(k T) - z_mid| / |z_mid| after k periods, and
//                 the growth rate per period fitted where 1e-12 < dev < 1e-3,
//                 compared with log |lambda_max| of the monodromy (stability.h);
//   admissibility exactly m impacts in the first period, at the predicted
//                 times, and no penetration (largest x_c - d in the samples);
//   manifold      (1-ipp) the largest distance of the simulated post-impact
//                 states to the analytic family {z0(T')}: drift along the
//                 family is allowed, leaving it is not; and a start at
//                 z0(T (1 + perturbation)), another point of the family;
//   perturbation  (exact, admissible orbits) a run from a start moved by
//                 `perturbation` |y| within the nontrivial Floquet subspace
//                 (no time shift, no step along the family, same energy to
//                 first order): its largest deviation over the periods
//                 relative to the initial one (bounded for a stable orbit)
//                 and its growth rate (log |lambda_max| for an unstable one);
//   energy drift.
// Verdicts (consistent / inconsistent, with the reason):
//   not admissible: the simulation must break in the first period (an extra
//                   impact or an impact away from the predicted times);
//   admissible, stable: the first period as predicted, and the deviation
//                   after all periods within the integrator's tolerance;
//   admissible, unstable: the first period as predicted, and the deviation
//                   grows at the rate the multipliers predict (within 30 %), or
//                   not at all (a floating-point fixed point of the map).
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "nsmodal/forced_orbit.h"
#include "nsmodal/model.h"
#include "nsmodal/orbit.h"
#include "nsmodal/response.h"
#include "nsmodal/simulate.h"
#include "nsmodal/stability.h"

namespace nsmodal {

struct ValidateOptions {
  int periods = 1000;
  std::vector<Integrator> integrators{Integrator::kExact};
  // Tolerances and steps of the integrators; validation's defaults differ
  // from a simulation's in the Moreau-Jean step (1e-4: 1,000 periods at 1e-3
  // drift past any useful tolerance).
  SimulateOptions simulate = Defaults();
  static SimulateOptions Defaults() {
    SimulateOptions o;
    o.step = 1e-4;
    return o;
  }
  // Relative size of the perturbed starts: of T for the on-manifold start, of
  // |y| for the off-family one.
  double perturbation = 1e-6;
  double exact_periodicity = 1e-9;  // exact: a stable orbit stays within this
  int threads = 0;                  // worker threads of ValidateOrbits (0: all cores)
  // Throws InputError naming the field: names("periods"), names("step"), ...
  // ("validate.periods" unless the caller says where the value came from).
  void Validate(const FieldNames& names = FieldNames("validate.")) const;
};

struct OrbitValidation {
  Orbit orbit;
  Integrator integrator = Integrator::kExact;
  Stability stability;
  std::vector<double> deviation;  // after k = 1, 2, ... periods (as far as the run went)
  double measured_growth = 0.0;   // per period; 0 when the deviation never grew
  long impacts = 0;
  long first_period_impacts = 0;
  // First period: max |t_k - predicted_k| over its impacts, paired in order;
  // absent when their count is not the predicted one (no pairing: an extra
  // or a missing impact, see first_period_impacts).
  std::optional<double> impact_time_error;
  double max_penetration = 0.0;    // max x_c - d over the samples
  double manifold_distance = -1.0;            // 1-ipp only, relative to |z0|
  double perturbed_manifold_distance = -1.0;  // 1-ipp only
  // Off-family perturbation (exact, admissible orbits; else 0 and -1).
  double perturbed_amplification = 0.0;  // max_k |z_k - z_mid| / |z_start - z_mid|
  double perturbed_growth = 0.0;         // per period; 0 when it never grew two decades
  int perturbed_periods = -1;            // periods run before saturation (0.1 |z|)
  double energy_drift = 0.0;
  double wall_time_s = 0.0;
  bool consistent = false;
  std::string reason;
  double DeviationAt(int k) const { return k >= 1 && k <= static_cast<int>(deviation.size()) ? deviation[k - 1] : -1.0; }
};

// One orbit with one integrator.
OrbitValidation ValidateOrbit(const Model& model, const Orbit& orbit, Integrator integrator,
                              const ValidateOptions& options);

// The simulations' work, estimated before they start (issue 29): the
// simulated time, options.periods times each admissible orbit's period plus
// two periods of each other one (a non-admissible orbit breaks in its first
// period, and the run stops there; validate.cc), in units of the fastest
// mode's oscillations (w_max / 2 pi) and of Moreau-Jean's steps (time /
// step), costed at the simulators' rates measured on the paper's system
// (Release, one core, user time; validate.cc), scaled by the model's size:
//   exact        1.7e-7 s x oscillations x (N + 8)
//   cvode        1.9e-6 s x oscillations x (N + 8)^2   (dense 2N x 2N Newton systems)
//   moreau-jean  5.6e-10 s x steps x (N + 8)^2         (dense matrix-vector steps)
// (The perturbed runs of the stable and unstable orbits are not counted:
// exact, and short beside the rest.) Beyond kMaxValidationSeconds in all,
// CheckValidationWork throws InputError naming names("periods") with the
// estimate and how to lower it.
inline constexpr double kMaxValidationSeconds = 3600.0;
// Within that time, fewer than kMaxValidationPeriods periods (each is a
// sample of the deviation, and a simulation takes at most 1e7 samples: at
// 1e7 periods, (1e7 T) / T can round above it).
inline constexpr long kMaxValidationPeriods = 10000000;
double ValidationSeconds(const Model& model, double simulated_time, const ValidateOptions& options);
void CheckValidationWork(const Model& model, double simulated_time, long orbits, const ValidateOptions& options,
                         const FieldNames& names = FieldNames("validate."));

// Every orbit with every integrator, on options.threads threads; progress(done, total).
// CheckValidationWork first (named by `names`).
std::vector<OrbitValidation> ValidateOrbits(const Model& model, const std::vector<Orbit>& orbits,
                                            const ValidateOptions& options,
                                            const std::function<void(long, long)>& progress = {},
                                            const FieldNames& names = FieldNames("validate."));

// A forced periodic orbit (forced_orbit.h) checked the same way: simulated
// from its state at t = 0 (the simulators start there: the forcing's phase
// is the orbit's) for options.periods response periods P, deviation_k =
// |z(k P) - z(0)| / |z(0)|, the first period's m impacts at the predicted
// times, and the same verdicts as for free orbits (not admissible: breaks in
// the first period; stable: stays within the integrator's tolerance;
// unstable: grows at log max |multiplier| per period, within 30 %). No
// perturbed or manifold runs: a forced orbit is isolated. When t = 0 falls
// within 1e-6 P of an impact the comparison points are impacts: the orbit is
// reported inconsistent with that reason, not judged.
struct ForcedOrbitValidation {
  ForcedOrbit orbit;
  Integrator integrator = Integrator::kExact;
  std::vector<double> deviation;  // after k = 1, 2, ... periods
  double measured_growth = 0.0;
  long impacts = 0, first_period_impacts = 0;
  std::optional<double> impact_time_error;  // as in OrbitValidation; absent also when not simulated
  double max_penetration = 0.0, wall_time_s = 0.0;
  bool consistent = false;
  std::string reason;
};
ForcedOrbitValidation ValidateForcedOrbit(const Model& model, const ForcedOrbit& orbit, Integrator integrator,
                                          const ValidateOptions& options);
std::vector<ForcedOrbitValidation> ValidateForcedOrbits(const Model& model, const std::vector<ForcedOrbit>& orbits,
                                                        const ValidateOptions& options,
                                                        const std::function<void(long, long)>& progress = {},
                                                        const FieldNames& names = FieldNames("validate."));

// response --validate (Python's response(validate=N)): every point of a
// response (response.h) simulated N periods with each integrator. A row
// per point and integrator, with the point's branch: response_validation.csv.
struct ForcedValidationRow {
  int branch = 0;  // 1-based
  ForcedOrbitValidation v;
};
struct ResponseValidation {
  std::vector<ForcedValidationRow> rows;  // point by point, the integrators in order
  long consistent = 0;                    // rows
  long failures = 0;                      // admissible points inconsistent with the exact integrator
};
// The options of N periods (0: none, which the faces skip; run as 1) with
// the integrators named: throws InputError naming names("periods") for
// N < 0, names("integrators") for an unknown name, and as
// ValidateOptions::Validate. Checked before any work.
ValidateOptions ResponseValidateOptions(long periods, const std::vector<std::string>& integrators, int threads,
                                        const FieldNames& names);
ResponseValidation ValidateResponse(const Model& model, const std::vector<ResponseRow>& rows,
                                    const ValidateOptions& options, const std::function<void(long, long)>& progress = {},
                                    const FieldNames& names = FieldNames("validate."));

// The verdict on a batch, and the numbers behind it.
//
// Acceptance: the batch passes when every admissible orbit is consistent
// with the exact integrator (the other integrators' inconsistencies are
// reported, not failures: they measure the integrator, not the orbit).
// The off-family perturbation (exact, admissible orbits) is summarised as:
// the largest amplification of a stable orbit over the run, and for the
// unstable orbits whose growth was measurable, how many grew within
// kRateTolerance of log |lambda_max| and the worst relative error.
struct ValidationReport {
  static constexpr double kRateTolerance = 0.05;
  struct Tally {
    long checked = 0, consistent = 0, inconsistent = 0;
  };
  long orbits = 0;
  int periods = 0;
  std::vector<std::pair<Integrator, Tally>> integrators;  // in the order of the options
  std::vector<std::size_t> inconsistent;                  // indices into the results, in order
  // Per integrator: up to five stable admissible orbits with the largest
  // final deviation, largest first.
  std::vector<std::pair<Integrator, std::vector<std::size_t>>> worst_stable;
  double perturbation = 0.0;  // relative size of the perturbed starts
  long stable_perturbed = 0;
  double stable_worst_amplification = 0.0;
  long unstable_rated = 0, unstable_within_tolerance = 0;
  double unstable_worst_rate_error = 0.0;
  std::vector<std::size_t> admissible_exact_failures;  // indices: what fails the batch
  bool passed() const { return admissible_exact_failures.empty(); }
};
ValidationReport SummarizeValidation(const std::vector<OrbitValidation>& results, const ValidateOptions& options,
                                     long orbits);

}  // namespace nsmodal
