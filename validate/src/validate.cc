#include "nsmodal/validate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <Eigen/Eigenvalues>

#include "nsmodal/error.h"
#include "nsmodal/flow.h"
#include "nsmodal/input_checks.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/parallel.h"

namespace nsmodal {
namespace {

// Tolerance on the deviation of a stable admissible orbit after K periods.
// exact: options.exact_periodicity (round-off: ~1e-12 after 10,000 periods,
// measured). cvode: its energy error grows steadily and the family is not
// isochronous (T depends on E), so its phase error grows ~ K^2: measured
// 1.1e-6 after 100 and 1.3e-4 after 1000 periods at rtol = 1e-10, i.e.
// ~1.1 rtol K^2; the tolerance is 10 rtol K^2. moreau-jean: first order,
// ~h per period: 10 h K, capped at 1.
double PeriodicityTolerance(Integrator integrator, const ValidateOptions& o, int periods) {
  switch (integrator) {
    case Integrator::kExact: return o.exact_periodicity;
    case Integrator::kCvode: return 10.0 * o.simulate.rtol * static_cast<double>(periods) * periods;
    case Integrator::kMoreauJean: return std::min(1.0, 10.0 * o.simulate.step * periods);
  }
  return 0.0;
}

// Tolerance on impact times in the first period: exact 1e-9 (found to
// ~1e-15), cvode 1e4 rtol (the root is found on its interpolant),
// moreau-jean 10 h (an impact is registered at a step end, <= 2h, and the
// O(h) velocity error of one impact shifts the next by O(h) times the flight
// in units of 1/w: up to 9.6 h measured on the paper's system).
double TimeTolerance(Integrator integrator, const ValidateOptions& o) {
  switch (integrator) {
    case Integrator::kExact: return 1e-9;
    case Integrator::kCvode: return 1e4 * o.simulate.rtol;
    case Integrator::kMoreauJean: return 10.0 * o.simulate.step;
  }
  return 0.0;
}

// The deepest penetration of x over every wall: max_j n_j . x - d_j.
double DeepestPenetration(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& x) {
  double p = -std::numeric_limits<double>::infinity();
  for (const Contact& c : model.contacts) p = std::max(p, c.Along(x) - c.gap);
  return p;
}

// Penetration allowed in the samples and impacts: exact, round-off of d;
// cvode, 1e3 (atol + rtol d), its position accuracy with room; moreau-jean,
// an event-capturing scheme, 2 h v_scale (one step of travel at the contact
// speed scale).
double PenetrationTolerance(Integrator integrator, const ValidateOptions& o, double gap, double v_scale) {
  switch (integrator) {
    case Integrator::kExact: return 1e-9 * gap;
    case Integrator::kCvode: return 1e3 * (o.simulate.atol + o.simulate.rtol * gap);
    case Integrator::kMoreauJean: return 2.0 * o.simulate.step * v_scale;
  }
  return 0.0;
}

// Distance of a post-impact state to the 1-ipp family {z0(T')}, T' near T.
// Only the family's state is needed: OneImpactState, O(N). (It used to build
// the whole evaluated orbit, whose NC3 search scans w_max T' / pi roots, four
// times per golden-section step, 320 times per impact: with w_max T ~ 1.3e5,
// a stiff chain at T = 2, 20 periods of this run did not end in 30 s.)
double FamilyDistance(const AnalysisBasis& b, const Eigen::VectorXd& z, double period, int contact) {
  auto dist = [&](double tp) { return (PhysicalOf(b, OneImpactState(b, tp, contact)) - z).norm(); };
  double lo = period * (1.0 - 1e-3), hi = period * (1.0 + 1e-3);
  for (int i = 0; i < 80; ++i) {  // golden section: the value at the minimum is what counts
    const double m1 = lo + 0.381966 * (hi - lo), m2 = lo + 0.618034 * (hi - lo);
    const bool left = dist(m1) < dist(m2);
    (left ? hi : lo) = left ? m2 : m1;
  }
  return dist(0.5 * (lo + hi));
}

// Largest distance to the family of the post-impact states of a run from z0.
double ManifoldRun(const Model& model, const AnalysisBasis& b, const Eigen::VectorXd& z0, double period, int periods,
                   SimulateOptions opt, int contact) {
  opt.t_end = periods * period + 0.5 * period;
  opt.sample_dt = 0.0;
  double worst = 0.0;
  SimulationObserver obs;
  obs.on_impact = [&](const ContactEvent& ev) { worst = std::max(worst, FamilyDistance(b, ev.after, period, contact)); };
  const int n = model.dofs();
  Simulate(model, z0.head(n), z0.tail(n), opt, obs);
  return worst / z0.norm();
}

// Growth of a deviation series: the least-squares slope of log(deviation) per
// period, from the first period where the deviation exceeds ten times `floor`
// (the integrator's own floor) to the last one before it first reaches 1e-2
// (saturation: past it the motion is nonlinear, and a trajectory that wanders
// back near the orbit, below 1e-2 again, says nothing of the growth rate).
// Measurable only over at least three periods and two decades: above a large
// floor (Moreau-Jean's ~1e-4) the deviation is dominated by the integrator's
// drift along the orbit, which grows polynomially, not at the multipliers'
// rate.
std::optional<double> FitGrowth(const std::vector<double>& dev, double floor) {
  int first = -1, last = -1;
  for (int k = 0; k < static_cast<int>(dev.size()); ++k) {
    if (dev[k] >= 1e-2) break;
    if (first < 0 && dev[k] > 10.0 * floor) first = k;
    last = k;
  }
  if (!(first >= 0 && last >= first + 3 && dev[last] >= 100.0 * dev[first])) return std::nullopt;
  double sk = 0.0, sl = 0.0, skk = 0.0, skl = 0.0;
  const int count = last - first + 1;
  for (int k = first; k <= last; ++k) {
    const double l = std::log(dev[k]);
    sk += k;
    sl += l;
    skk += static_cast<double>(k) * k;
    skl += k * l;
  }
  return (count * skl - sk * sl) / (count * skk - sk * sk);
}

// A run of the exact integrator from y_mid + delta |y_mid| u, u a unit vector
// in the nontrivial Floquet subspace: the real span of the eigenvectors of the
// monodromy whose multipliers are not the trivial pair at 1. That excludes a
// time shift along the flow (a constant offset that, seen in |z - z_mid|,
// makes growth look faster or slower while it is comparable) and a step along
// the family (which the family, not being isochronous, turns into a drift);
// it also keeps the energy to first order (y is a left eigenvector for 1).
// The monodromy is taken at t = 0; S(t_mid) carries u to the start.
// Returns the deviation from the orbit's z_mid after each period, divided by
// the initial one.
std::vector<double> PerturbedRun(const Model& model, const AnalysisBasis& b, const Orbit& orbit,
                                 const Eigen::VectorXd& y_mid, double t_mid, double period, int periods,
                                 double delta, SimulateOptions opt) {
  Eigen::EigenSolver<Eigen::MatrixXd> es(Monodromy(b, orbit));
  Eigen::VectorXd u = Eigen::VectorXd::Zero(y_mid.size());
  for (int k = 0; k < es.eigenvalues().size(); ++k) {
    // The trivial pair is within ~1e-6 of 1 (stability.h: a Jordan block split
    // by ~sqrt(eps)); 1e-4 keeps any nontrivial multiplier measurably away.
    if (std::abs(es.eigenvalues()[k] - 1.0) < 1e-4) continue;
    const Eigen::VectorXcd v = es.eigenvectors().col(k).normalized();
    u += v.real() + v.imag();
  }
  if (u.norm() == 0.0) return {};
  Flow(b, t_mid, u);  // S(t_mid) is linear: the same map carries perturbations
  u.normalize();
  const Eigen::VectorXd z_mid = PhysicalOf(b, y_mid);
  const Eigen::VectorXd z_start = PhysicalOf(b, y_mid + delta * y_mid.norm() * u);
  const double initial = (z_start - z_mid).norm();
  opt.integrator = Integrator::kExact;
  opt.t_end = periods * period;
  opt.sample_dt = period;
  std::vector<double> out;
  SimulationObserver obs;
  obs.on_sample = [&](double t, const Eigen::VectorXd& z) {
    if (t > 0.0) out.push_back((z - z_mid).norm() / initial);
  };
  // Saturated (the perturbation reached the orbit's own size): stop.
  obs.stop_requested = [&] { return !out.empty() && out.back() * initial > 0.1 * z_mid.norm(); };
  const int n = model.dofs();
  Simulate(model, z_start.head(n), z_start.tail(n), opt, obs);
  return out;
}

// What a run showed, for the verdict (validate.h: the same rules for free
// and forced orbits).
struct RunFacts {
  bool admissible, stable;
  int impacts;
  double predicted_rate;  // log |lambda_max| per period
  long first_period_impacts;
  std::optional<double> impact_time_error;  // absent: not the predicted count of impacts
  double max_penetration;
  const std::vector<double>& deviation;
  bool broken;
  std::optional<double> growth;
  double floor;
  const SimulationSummary& summary;
  // The start's round-off (kStartRoundOff of |z|) grown over the first period
  // of an unstable orbit by up to |lambda_max| = e^rate, as a time error at
  // the slowest impact (/ min v_c): an impact damper's orbit near grazing has
  // |lambda_max| ~ 1e6 and v_c ~ 1e-3, so its impact times are only predicted
  // to ~1e-6 from a start exact to round-off. 0 where not computed.
  double amplified_time = 0.0;
};

// The relative error of a start state computed in double precision (a few
// ulps of each component).
constexpr double kStartRoundOff = 1e-15;

void Judge(const RunFacts& f, Integrator integrator, const ValidateOptions& options, double ptol, bool* consistent,
           std::string* reason) {
  // Beside the integrator's own accuracy, the start's round-off carried over
  // the first period (RunFacts::amplified_time).
  const double ttol = TimeTolerance(integrator, options) + f.amplified_time;
  const bool first_period_ok =
      f.first_period_impacts == f.impacts && (f.impacts == 0 || (f.impact_time_error && *f.impact_time_error <= ttol)) &&
      f.max_penetration <= ptol;
  const std::string who = ToString(integrator);
  bool& ok = *consistent;
  std::string& why = *reason;
  if (f.summary.status == SimulationStatus::kSolverError || f.summary.status == SimulationStatus::kStepLimit) {
    ok = false;
    why = who + " stopped: " + f.summary.message;
  } else if (!f.admissible) {
    ok = !first_period_ok;
    why = ok ? "breaks as predicted (not admissible): " + std::to_string(f.first_period_impacts) +
                   " impacts in the first period"
             : "not admissible, yet the first period looks admissible to " + who;
  } else if (!first_period_ok) {
    ok = false;
    why = "first period: " + std::to_string(f.first_period_impacts) + " impacts (expected " +
          std::to_string(f.impacts) + "), time error " +
          (f.impact_time_error ? FormatEstimate(*f.impact_time_error) : std::string("n/a")) + ", penetration " +
          FormatEstimate(f.max_penetration);
  } else if (f.stable) {
    const double tol = PeriodicityTolerance(integrator, options, options.periods);
    const double final_dev = f.deviation.empty() ? 0.0 : f.deviation.back();
    ok = !f.broken && static_cast<int>(f.deviation.size()) == options.periods && final_dev <= tol;
    why = ok ? "stable and periodic: deviation " + FormatEstimate(final_dev) + " after " + std::to_string(options.periods) +
                   " periods"
             : "stable orbit drifted: deviation " + FormatEstimate(final_dev) + " > " + FormatEstimate(tol);
  } else {
    const double max_dev = f.deviation.empty() ? 0.0 : *std::max_element(f.deviation.begin(), f.deviation.end());
    const double measured = f.growth ? *f.growth : 0.0;
    if (max_dev <= 1e-12) {
      ok = true;
      why = "unstable, but round-off never grew (a floating-point fixed point of the map)";
    } else if (!f.growth) {
      ok = true;
      why = "unstable; growth not measurable above " + who + "'s error floor (" + FormatEstimate(f.floor) +
            " after one period): first period as predicted";
    } else if (measured > 0.0 && std::abs(measured - f.predicted_rate) <= 0.3 * f.predicted_rate) {
      ok = true;
      why = "unstable: deviation grows " + FormatEstimate(measured) + " per period, multipliers predict " +
            FormatEstimate(f.predicted_rate);
    } else {
      ok = false;
      why = "unstable: measured growth " + FormatEstimate(measured) + " per period, predicted " + FormatEstimate(f.predicted_rate);
    }
  }
}

}  // namespace

void ValidateOptions::Validate(const FieldNames& names) const {
  if (periods < 1 || periods > 100000000) {
    throw InputError(names("periods"), "must lie in [1, 1e8], got " + std::to_string(periods));
  }
  if (integrators.empty()) throw InputError(names("integrators"), "must name at least one integrator");
  CheckThreads(threads, names("threads"));
  if (!(perturbation > 0.0 && perturbation < 0.1)) {
    throw InputError(names("perturbation"), "must lie in (0, 0.1), got " + FormatValue(perturbation));
  }
  simulate.Validate(names);
}

OrbitValidation ValidateOrbit(const Model& model, const Orbit& orbit, Integrator integrator,
                              const ValidateOptions& options) {
  const AnalysisBasis b(model);
  const int n = model.dofs();
  const double period = orbit.period;
  OrbitValidation v;
  v.orbit = orbit;
  v.integrator = integrator;
  v.stability = OrbitStability(b, orbit);

  // Start in the middle of the first flight, where no comparison point k T
  // meets an impact. A non-admissible orbit may be beyond the wall there: it
  // starts at z0 itself, on the wall.
  const double first_flight = orbit.times.empty() ? period : orbit.times.front();
  const double t_mid = orbit.admissible ? 0.5 * first_flight : 0.0;
  Eigen::VectorXd y_mid = orbit.y0;
  Flow(b, t_mid, y_mid);
  const Eigen::VectorXd z_mid = PhysicalOf(b, y_mid);
  std::vector<double> predicted;  // impact times in the first period of the run
  for (double t : orbit.times) predicted.push_back(t - t_mid);
  predicted.push_back(period - t_mid);

  SimulateOptions opt = options.simulate;
  opt.integrator = integrator;
  opt.t_end = options.periods * period;
  opt.sample_dt = period;
  SimulationObserver obs;
  // A run has left its orbit when the deviation exceeds 0.1 (and, for a
  // stable orbit, twice what the integrator may drift): no need to go on.
  const double give_up = v.stability.stable && orbit.admissible
                             ? std::max(0.1, 2.0 * PeriodicityTolerance(integrator, options, options.periods))
                             : 0.1;
  bool broken = false;
  double time_error = 0.0;  // over the first period's impacts that have a predicted time
  bool wrong_contact = false;  // a first-period impact on another contact than the sequence's
  // The run's k-th impact of the first period ends flight k + 1 (from t_mid):
  // the sequence's impact k + 1, the last one the impact at T (the first).
  std::vector<int> sequence = orbit.sequence;
  if (sequence.empty()) sequence.assign(orbit.impacts, 0);
  obs.on_sample = [&](double t, const Eigen::VectorXd& z) {
    v.max_penetration = std::max(v.max_penetration, DeepestPenetration(model, z.head(n)));
    if (t == 0.0) return;
    const double dev = (z - z_mid).norm() / z_mid.norm();
    v.deviation.push_back(dev);
    broken = broken || dev > give_up;
  };
  obs.on_impact = [&](const ContactEvent& ev) {
    ++v.impacts;
    v.max_penetration = std::max(v.max_penetration, DeepestPenetration(model, ev.before.head(n)));
    if (ev.t < period - t_mid + 0.5 * first_flight) {  // the first period of the run
      const std::size_t k = static_cast<std::size_t>(v.first_period_impacts++);
      if (k < predicted.size()) {
        time_error = std::max(time_error, std::abs(ev.t - predicted[k]));
        wrong_contact = wrong_contact || ev.contact != sequence[(k + 1) % sequence.size()];
      }
    }
  };
  obs.stop_requested = [&] { return broken; };
  const SimulationSummary sum = Simulate(model, z_mid.head(n), z_mid.tail(n), opt, obs);
  // Impacts on other walls than the sequence's have no predicted times.
  if (v.first_period_impacts == orbit.impacts && orbit.impacts > 0 && !wrong_contact) v.impact_time_error = time_error;
  v.energy_drift = sum.energy_drift;
  v.wall_time_s = sum.wall_time_s;

  const double floor = v.deviation.empty() ? 0.0 : std::max(1e-13, v.deviation.front());
  const std::optional<double> growth = FitGrowth(v.deviation, floor);
  if (growth) v.measured_growth = *growth;

  if (integrator == Integrator::kExact && orbit.admissible) {
    const std::vector<double> amp =
        PerturbedRun(model, b, orbit, y_mid, t_mid, period, options.periods, options.perturbation, opt);
    v.perturbed_periods = static_cast<int>(amp.size());
    v.perturbed_amplification = amp.empty() ? 0.0 : *std::max_element(amp.begin(), amp.end());
    // amp is relative to the initial perturbation; times `perturbation` it is
    // on the orbit's scale, where FitGrowth's saturation (1e-2) applies, and
    // its floor is `perturbation` itself (growth counts from 10x the start).
    std::vector<double> scaled = amp;
    for (double& a : scaled) a *= options.perturbation;
    if (const std::optional<double> g = FitGrowth(scaled, options.perturbation)) v.perturbed_growth = *g;
  }

  if (orbit.impacts == 1 && integrator == Integrator::kExact) {
    const int manifold_periods = std::min(options.periods, 20);
    v.manifold_distance = ManifoldRun(model, b, orbit.z0, period, manifold_periods, opt, sequence[0]);
    const Orbit shifted = OneImpactOrbit(b, period * (1.0 + options.perturbation), {}, sequence[0]);
    v.perturbed_manifold_distance =
        ManifoldRun(model, b, shifted.z0, shifted.period, manifold_periods, opt, sequence[0]);
  }

  // Verdict.
  RunFacts facts{orbit.admissible, v.stability.stable, orbit.impacts, v.stability.growth_per_period,
                 v.first_period_impacts, v.impact_time_error, v.max_penetration, v.deviation, broken,
                 growth, floor, sum};
  // The scales of the walls struck: the fastest normal speed and the smallest gap.
  double r_norm2 = 0.0, gap = std::numeric_limits<double>::infinity();
  for (int j : sequence) {
    r_norm2 = std::max(r_norm2, b.contacts[j].r_norm2);
    gap = std::min(gap, b.contacts[j].gap);
  }
  const double v_scale = std::sqrt(2.0 * orbit.energy * r_norm2);
  Judge(facts, integrator, options, PenetrationTolerance(integrator, options, gap, v_scale), &v.consistent, &v.reason);
  if (wrong_contact) v.reason += " (a first-period impact struck another wall than the sequence's)";
  return v;
}

namespace {

// Every orbit with every integrator on options.threads threads: result
// i = orbit i / k with integrator i % k (k integrators).
template <class Result, class OrbitT, class One>
std::vector<Result> EveryOrbitAndIntegrator(const Model& model, const std::vector<OrbitT>& orbits,
                                            const ValidateOptions& options,
                                            const std::function<void(long, long)>& progress,
                                            const FieldNames& names, One one) {
  options.Validate(names);
  double simulated = 0.0;  // time, as ValidationSeconds counts it
  for (const OrbitT& o : orbits) simulated += (o.admissible ? options.periods : std::min(options.periods, 2)) * o.period;
  CheckValidationWork(model, simulated, static_cast<long>(orbits.size()), options, names);
  const long per_orbit = static_cast<long>(options.integrators.size());
  std::vector<Result> out(orbits.size() * per_orbit);
  ParallelFor(
      static_cast<long>(out.size()), options.threads,
      [&](long i) { out[i] = one(orbits[i / per_orbit], options.integrators[i % per_orbit]); }, progress);
  return out;
}

}  // namespace

double ValidationSeconds(const Model& model, double simulated_time, const ValidateOptions& options) {
  // Rates measured with `nsmodal simulate` on configs/paper-simulate.toml
  // (N = 2, w_max = 2.11, about 0.15 impacts per time unit), user time:
  // exact 0.57 s for 1e6 time units (3.4e5 oscillations); CVODE (Adams,
  // rtol 1e-10) 6.2 s for 1e5; Moreau-Jean 0.56 s for 1e7 steps. Checked
  // on the README's validation of 2:30:0.5 at 1,000 periods: estimated
  // within 3.5 times above the measured CPU time of each integrator.
  const double n = model.dofs() + 8.0;
  const double oscillations = simulated_time * MakeModalBasis(model).omega.maxCoeff() / (2.0 * M_PI);
  double seconds = 0.0;
  for (Integrator i : options.integrators) {
    switch (i) {
      case Integrator::kExact: seconds += 1.7e-7 * oscillations * n; break;
      case Integrator::kCvode: seconds += 1.9e-6 * oscillations * n * n; break;
      case Integrator::kMoreauJean: seconds += 5.6e-10 * (simulated_time / options.simulate.step) * n * n; break;
    }
  }
  return seconds;
}

void CheckValidationWork(const Model& model, double simulated_time, long orbits, const ValidateOptions& options,
                         const FieldNames& names) {
  const double seconds = ValidationSeconds(model, simulated_time, options);
  if (seconds <= kMaxValidationSeconds) {
    // Within the time, still within the samples: a validation samples the
    // state once a period (its deviation), and a simulation takes at most
    // 1e7 samples (SimulateOptions::Validate), which would otherwise refuse
    // it naming sample_dt, a setting the user never gave.
    // At the bound itself (periods T) / T can round above 1e7: so below it.
    if (options.periods >= kMaxValidationPeriods) {
      throw InputError(names("periods"), "is " + std::to_string(options.periods) + ": a validation samples every period, fewer than " +
                                             FormatEstimate(kMaxValidationPeriods) + " periods (use fewer periods)");
    }
    return;
  }
  throw InputError(names("periods"),
                   std::to_string(orbits) + " orbits over " + std::to_string(options.periods) + " periods with " +
                       std::to_string(options.integrators.size()) + " integrator(s): an estimated " + FormatEstimate(seconds) +
                       " s of simulation on one core (" + FormatEstimate(simulated_time) +
                       " time units); the limit is " + FormatEstimate(kMaxValidationSeconds) +
                       " s: use fewer periods, fewer orbits (a shorter range or a larger STEP), fewer integrators "
                       "(exact is the fastest by far) or, for moreau-jean, a larger step");
}

std::vector<OrbitValidation> ValidateOrbits(const Model& model, const std::vector<Orbit>& orbits,
                                            const ValidateOptions& options,
                                            const std::function<void(long, long)>& progress,
                                            const FieldNames& names) {
  return EveryOrbitAndIntegrator<OrbitValidation>(
      model, orbits, options, progress, names,
      [&](const Orbit& o, Integrator integrator) { return ValidateOrbit(model, o, integrator, options); });
}

ForcedOrbitValidation ValidateForcedOrbit(const Model& model, const ForcedOrbit& orbit, Integrator integrator,
                                          const ValidateOptions& options) {
  const ForcedProblem problem = orbit.sequence.empty()
                                    ? ForcedProblem(model, orbit.impacts, orbit.periods, orbit.frequency, orbit.amplitude)
                                    : ForcedProblem(model, orbit.sequence, orbit.periods, orbit.frequency, orbit.amplitude);
  const Model& m = problem.model();
  const int n = m.dofs();
  const double period = orbit.period;
  ForcedOrbitValidation v;
  v.orbit = orbit;
  v.integrator = integrator;
  // The predicted impact times in [0, P), in time order, with their contacts.
  std::vector<std::pair<double, int>> predicted;
  double nearest = period;
  for (std::size_t i = 0; i < orbit.times.size(); ++i) {
    const double t = orbit.times[i];
    const double p = t - period * std::floor(t / period);
    predicted.emplace_back(p, orbit.sequence.empty() ? 0 : orbit.sequence[i]);
    nearest = std::min({nearest, p, period - p});
  }
  std::sort(predicted.begin(), predicted.end());
  if (nearest < 1e-6 * period) {
    v.reason = "t = 0 lies on an impact (within " + FormatEstimate(nearest) + "): the comparison points k P are impacts";
    return v;
  }
  const Eigen::VectorXd z0 = problem.StateAt(orbit, 0.0);
  if (DeepestPenetration(m, z0.head(n)) > 1e-12 * problem.gap_scale()) {
    // Only a non-admissible orbit can be beyond a wall: no motion follows it.
    v.consistent = !orbit.admissible;
    v.reason = (m.contacts.size() == 1
                    ? "x_c(0) = " + FormatEstimate(m.contacts[0].Along(z0.head(n))) + " lies beyond the obstacle: "
                    : "x(0) lies beyond a wall (by " + FormatEstimate(DeepestPenetration(m, z0.head(n))) + "): ") +
               (orbit.admissible ? "yet the orbit was found admissible" : "it breaks, as predicted (not admissible)");
    return v;
  }
  SimulateOptions opt = options.simulate;
  opt.integrator = integrator;
  opt.t_end = options.periods * period;
  opt.sample_dt = period;
  const double predicted_rate = std::log(orbit.max_multiplier);
  const double give_up = orbit.stable && orbit.admissible
                             ? std::max(0.1, 2.0 * PeriodicityTolerance(integrator, options, options.periods))
                             : 0.1;
  bool broken = false;
  double time_error = 0.0;  // over the first period's impacts that have a predicted time
  bool wrong_contact = false;  // a first-period impact on another contact than predicted
  SimulationObserver obs;
  obs.on_sample = [&](double t, const Eigen::VectorXd& z) {
    v.max_penetration = std::max(v.max_penetration, DeepestPenetration(m, z.head(n)));
    if (t == 0.0) return;
    const double dev = (z - z0).norm() / z0.norm();
    v.deviation.push_back(dev);
    broken = broken || dev > give_up;
  };
  obs.on_impact = [&](const ContactEvent& ev) {
    ++v.impacts;
    v.max_penetration = std::max(v.max_penetration, DeepestPenetration(m, ev.before.head(n)));
    if (ev.t < period) {
      const std::size_t k = static_cast<std::size_t>(v.first_period_impacts++);
      if (k < predicted.size()) {
        time_error = std::max(time_error, std::abs(ev.t - predicted[k].first));
        wrong_contact = wrong_contact || ev.contact != predicted[k].second;
      }
    }
  };
  obs.stop_requested = [&] { return broken; };
  const SimulationSummary sum = Simulate(m, z0.head(n), z0.tail(n), opt, obs);
  // (A linear response, impacts = 0, has no impact times to compare.)
  if (v.first_period_impacts == orbit.impacts && orbit.impacts > 0 && !wrong_contact) v.impact_time_error = time_error;
  v.wall_time_s = sum.wall_time_s;
  const double floor = v.deviation.empty() ? 0.0 : std::max(1e-13, v.deviation.front());
  const std::optional<double> growth = FitGrowth(v.deviation, floor);
  if (growth) v.measured_growth = *growth;
  // The velocity scale of the penetration tolerance: the largest impact velocity.
  double v_scale = 0.0;
  for (std::size_t i = 0; i < orbit.before.size(); ++i) {
    const Contact& c = m.contacts[orbit.sequence.empty() ? 0 : orbit.sequence[i]];
    v_scale = std::max(v_scale, std::abs(c.Along(orbit.before[i].tail(n))));
  }
  RunFacts facts{orbit.admissible, orbit.stable, orbit.impacts, predicted_rate, v.first_period_impacts,
                 v.impact_time_error, v.max_penetration, v.deviation, broken, growth, floor, sum};
  if (orbit.admissible && !orbit.stable && orbit.impacts > 0 && orbit.min_impact_velocity > 0.0) {
    facts.amplified_time = orbit.max_multiplier * kStartRoundOff * z0.norm() / orbit.min_impact_velocity;
  }
  Judge(facts, integrator, options, PenetrationTolerance(integrator, options, problem.gap_scale(), v_scale),
        &v.consistent, &v.reason);
  if (wrong_contact) v.reason += " (a first-period impact struck another wall than predicted)";
  return v;
}

std::vector<ForcedOrbitValidation> ValidateForcedOrbits(const Model& model, const std::vector<ForcedOrbit>& orbits,
                                                        const ValidateOptions& options,
                                                        const std::function<void(long, long)>& progress,
                                                        const FieldNames& names) {
  return EveryOrbitAndIntegrator<ForcedOrbitValidation>(
      model, orbits, options, progress, names,
      [&](const ForcedOrbit& o, Integrator integrator) { return ValidateForcedOrbit(model, o, integrator, options); });
}

ValidateOptions ResponseValidateOptions(long periods, const std::vector<std::string>& integrators, int threads,
                                        const FieldNames& names) {
  ValidateOptions o;
  o.periods = static_cast<int>(std::clamp(periods, 1L, static_cast<long>(std::numeric_limits<int>::max())));
  o.integrators.clear();
  for (const std::string& name : integrators) o.integrators.push_back(ParseIntegrator(name, names("integrators")));
  o.threads = threads;
  if (periods < 0) throw InputError(names("periods"), "must be >= 0, got " + std::to_string(periods));
  o.Validate(names);
  return o;
}

ResponseValidation ValidateResponse(const Model& model, const std::vector<ResponseRow>& rows,
                                    const ValidateOptions& options, const std::function<void(long, long)>& progress,
                                    const FieldNames& names) {
  std::vector<ForcedOrbit> orbits;
  for (const ResponseRow& r : rows) orbits.push_back(r.orbit);
  ResponseValidation out;
  const std::vector<ForcedOrbitValidation> results = ValidateForcedOrbits(model, orbits, options, progress, names);
  for (std::size_t i = 0; i < results.size(); ++i) {
    const ForcedOrbitValidation& v = results[i];
    out.rows.push_back({rows[i / options.integrators.size()].branch, v});
    out.consistent += v.consistent ? 1 : 0;
    out.failures += !v.consistent && v.integrator == Integrator::kExact && v.orbit.admissible ? 1 : 0;
  }
  return out;
}

ValidationReport SummarizeValidation(const std::vector<OrbitValidation>& results, const ValidateOptions& options,
                                     long orbits) {
  ValidationReport r;
  r.orbits = orbits;
  r.periods = options.periods;
  r.perturbation = options.perturbation;
  for (Integrator integrator : options.integrators) {
    ValidationReport::Tally t;
    std::vector<std::size_t> stable;
    for (std::size_t i = 0; i < results.size(); ++i) {
      const OrbitValidation& v = results[i];
      if (v.integrator != integrator) continue;
      ++t.checked;
      ++(v.consistent ? t.consistent : t.inconsistent);
      if (v.orbit.admissible && v.stability.stable && !v.deviation.empty()) stable.push_back(i);
    }
    std::stable_sort(stable.begin(), stable.end(), [&](std::size_t x, std::size_t y) {
      return results[x].deviation.back() > results[y].deviation.back();
    });
    if (stable.size() > 5) stable.resize(5);
    r.integrators.emplace_back(integrator, t);
    r.worst_stable.emplace_back(integrator, std::move(stable));
  }
  for (std::size_t i = 0; i < results.size(); ++i) {
    const OrbitValidation& v = results[i];
    if (!v.consistent) r.inconsistent.push_back(i);
    if (!v.consistent && v.orbit.admissible && v.integrator == Integrator::kExact) {
      r.admissible_exact_failures.push_back(i);
    }
    if (v.integrator != Integrator::kExact || !v.orbit.admissible || v.perturbed_periods < 0) continue;
    if (v.stability.stable) {
      ++r.stable_perturbed;
      r.stable_worst_amplification = std::max(r.stable_worst_amplification, v.perturbed_amplification);
    } else if (v.perturbed_growth > 0.0) {
      const double err = std::abs(v.perturbed_growth / v.stability.growth_per_period - 1.0);
      ++r.unstable_rated;
      r.unstable_within_tolerance += err <= ValidationReport::kRateTolerance;
      r.unstable_worst_rate_error = std::max(r.unstable_worst_rate_error, err);
    }
  }
  return r;
}

}  // namespace nsmodal
