#include "nsmodal/explore.h"

#include "nsmodal/check.h"
#include "nsmodal/parallel.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_multimin.h>

#include <algorithm>
#include <functional>
#include <cmath>
#include <limits>
#include <optional>

#include "nsmodal/admissibility.h"
#include "nsmodal/error.h"
#include "nsmodal/flow.h"
#include "nsmodal/return_map.h"
#include "nsmodal/stability.h"
#include "nsmodal/stop.h"

namespace nsmodal {
namespace {

struct Candidate {
  double phi;
  Eigen::VectorXd y0;
};

// The wall of each impact: d_{j_i} (a sequence is `impacts` contacts).
Eigen::VectorXd Gaps(const AnalysisBasis& b, const std::vector<int>& sequence, int impacts) {
  Eigen::VectorXd d(impacts);
  for (int i = 0; i < impacts; ++i) d[i] = b.contacts[sequence.empty() ? 0 : sequence[i]].gap;
  return d;
}

// phi(times) and the y0 that realises it (see explore.h).
Candidate Objective(const AnalysisBasis& b, const std::vector<double>& times, double period, int impacts,
                    const std::vector<int>& sequence) {
  const int k = impacts % 2 == 0 ? 2 : 1;
  KernelContacts kc;
  if (!KernelAtImpacts(b, times, period, k, kc, sequence)) return {std::numeric_limits<double>::infinity(), {}};
  const Eigen::VectorXd rhs = Gaps(b, sequence, impacts);
  const Eigen::VectorXd alpha = kc.c.jacobiSvd(Eigen::ComputeThinU | Eigen::ComputeThinV).solve(rhs);
  const double misfit = (kc.c * alpha - rhs).norm() / (rhs.maxCoeff() * std::sqrt(impacts));
  const double sigma = impacts % 2 == 0 ? kc.sigma_k : 0.0;
  return {sigma + misfit, kc.basis * alpha};
}

struct NmParams {
  const AnalysisBasis* b;
  double period;
  int impacts;
  const std::vector<int>* sequence;
};

double NmObjective(const gsl_vector* v, void* p) {
  const auto* prm = static_cast<const NmParams*>(p);
  std::vector<double> times(v->size);
  for (std::size_t i = 0; i < v->size; ++i) times[i] = gsl_vector_get(v, i);
  const double phi = Objective(*prm->b, times, prm->period, prm->impacts, *prm->sequence).phi;
  return std::isfinite(phi) ? phi : 1e6;
}

std::vector<double> Polish(const AnalysisBasis& b, std::vector<double> times, double period, int impacts,
                           const std::vector<int>& sequence) {
  // NmObjective never returns a non-finite value, so GSL's handler is never
  // reached (gsl_call.h).
  const std::size_t n = times.size();
  NmParams prm{&b, period, impacts, &sequence};
  gsl_multimin_function f{&NmObjective, n, &prm};
  gsl_vector* x = gsl_vector_alloc(n);
  gsl_vector* step = gsl_vector_alloc(n);
  for (std::size_t i = 0; i < n; ++i) {
    gsl_vector_set(x, i, times[i]);
    gsl_vector_set(step, i, 0.25 * period / (impacts * 4.0));
  }
  gsl_multimin_fminimizer* s = gsl_multimin_fminimizer_alloc(gsl_multimin_fminimizer_nmsimplex2, n);
  gsl_multimin_fminimizer_set(s, &f, x, step);
  for (int iter = 0; iter < 2000; ++iter) {
    if (gsl_multimin_fminimizer_iterate(s) != GSL_SUCCESS) break;
    if (gsl_multimin_test_size(gsl_multimin_fminimizer_size(s), 1e-13 * period) == GSL_SUCCESS) break;
  }
  for (std::size_t i = 0; i < n; ++i) times[i] = gsl_vector_get(s->x, i);
  gsl_multimin_fminimizer_free(s);
  gsl_vector_free(step);
  gsl_vector_free(x);
  return times;
}

// A potential m-ipp orbit that is a lower-m orbit repeated: its impact times
// form a periodic pattern (t_{i+p} = t_i + T p / m for some divisor p of m),
// and so does its sequence (j_{i+p} = j_i).
bool RepeatsLowerOrbit(const std::vector<double>& times, double period, int impacts,
                       const std::vector<int>& sequence) {
  std::vector<double> all{0.0};
  all.insert(all.end(), times.begin(), times.end());
  // Two impacts of one contact at one instant cancel (N^2 = I for e = 1): an
  // orbit with fewer impacts.
  if (CoincidentImpacts(times, period, impacts, sequence, true)) return true;
  for (int p = 1; p < impacts; ++p) {
    if (impacts % p != 0) continue;
    const double shift = period * p / impacts;
    // (p divides m: the sequence repeating with period p is its rotation by p.)
    bool ok = SequenceKeptBy(sequence, p);
    for (int i = 0; i + p < impacts && ok; ++i) ok = std::abs(all[i + p] - all[i] - shift) < 1e-6 * period;
    if (ok) return true;
  }
  return false;
}

// Flight durations (t2, t3 - t2, ..., T - tm): the same orbit started at
// another impact has these rotated.
std::vector<double> Intervals(const std::vector<double>& times, double period) {
  std::vector<double> d;
  double prev = 0.0;
  for (double t : times) {
    d.push_back(t - prev);
    prev = t;
  }
  d.push_back(period - prev);
  return d;
}

// The same orbit started at another impact: the flights rotated by a shift
// that maps the sequence onto itself.
bool SameOrbit(const Orbit& a, const std::vector<double>& times, double period, const std::vector<int>& sequence) {
  if (a.period != period) return false;
  const std::vector<double> x = Intervals(a.times, period), y = Intervals(times, period);
  const std::size_t m = x.size();
  for (std::size_t shift = 0; shift < m; ++shift) {
    if (!SequenceKeptBy(sequence, static_cast<int>(shift))) continue;
    double dist = 0.0;
    for (std::size_t i = 0; i < m; ++i) dist = std::max(dist, std::abs(x[i] - y[(i + shift) % m]));
    if (dist < 1e-6 * period) return true;
  }
  return false;
}

// Smallest |v_c| just before an impact relative to the largest: ~0 means a
// grazing contact, i.e. an orbit with fewer true impacts touching d (Fig. 9).
double GrazingRatio(const AnalysisBasis& b, const Orbit& o) {
  Eigen::VectorXd y = o.y0;
  double prev = 0.0, vmin = INFINITY, vmax = 0.0;
  std::vector<double> ends = o.times;
  ends.push_back(o.period);
  const int m = static_cast<int>(ends.size());
  for (int k = 0; k < m; ++k) {
    Flow(b, ends[k] - prev, y);
    prev = ends[k];
    // The flight ends at impact k + 1 (mod m): its own contact.
    const ModalContact& c = b.contacts[o.sequence.empty() ? 0 : o.sequence[(k + 1) % m]];
    const double v = std::abs(ContactVelocity(b, c, y));
    vmin = std::min(vmin, v);
    vmax = std::max(vmax, v);
    Impact(b, c, AnalysisBasis::kRestitution, y);
  }
  return vmax > 0.0 ? vmin / vmax : 0.0;
}

void Enumerate(int impacts, int grid, std::vector<int>& idx, int pos, const std::function<void()>& visit) {
  if (pos == impacts - 1) {
    visit();
    return;
  }
  const int start = pos == 0 ? 1 : idx[pos - 1] + 1;
  for (int j = start; j < grid; ++j) {
    idx[pos] = j;
    Enumerate(impacts, grid, idx, pos + 1, visit);
  }
}

}  // namespace

namespace {

// The search at one period.
ExploreReport ExploreOnePeriod(const AnalysisBasis& b, double period, const ExploreOptions& options) {
  const int m = options.impacts;
  const std::vector<int>& seq = options.sequence;
  ExploreReport report;
  report.impacts = m;
  report.best_phi_new = std::numeric_limits<double>::infinity();
  {
    std::vector<std::pair<double, std::vector<double>>> best;
    std::vector<int> idx(m - 1);
    std::vector<double> times(m - 1);
    Enumerate(m, options.grid, idx, 0, [&] {
      for (int i = 0; i < m - 1; ++i) times[i] = period * idx[i] / options.grid;
      ++report.samples;
      if (m % 2 == 1) ++report.kernel_dimension_histogram[KernelDimension(MatrixA(b, times, period, seq), 1e-8)];
      const double phi = Objective(b, times, period, m, seq).phi;
      best.emplace_back(phi, times);
    });
    const std::size_t keep = std::min<std::size_t>(best.size(), options.starts_per_period);
    std::partial_sort(best.begin(), best.begin() + keep, best.end(),
                      [](const auto& x, const auto& y) { return x.first < y.first; });
    for (std::size_t s = 0; s < keep; ++s) {
      const std::vector<double> polished = Polish(b, best[s].second, period, m, seq);
      const Candidate cand = Objective(b, polished, period, m, seq);
      const bool repeated = RepeatsLowerOrbit(polished, period, m, seq);
      if (!repeated) report.best_phi_new = std::min(report.best_phi_new, cand.phi);
      if (!(cand.phi < options.potential_tol)) continue;
      bool seen = false;
      for (const ExploreFinding& f : report.findings) seen = seen || SameOrbit(f.orbit, polished, period, seq);
      if (seen) continue;
      ExploreFinding finding;
      finding.orbit = EvaluateOrbit(b, cand.y0, polished, period, {}, seq);
      finding.grazing_ratio = GrazingRatio(b, finding.orbit);
      // A contact velocity below 1e-6 of the largest is a touch, not an impact.
      finding.kind = repeated                                                   ? "repeated-lower-m"
                     : CoincidentImpacts(polished, period, m, seq, false) ? "simultaneous-impacts"
                     : finding.grazing_ratio < 1e-6                       ? "grazing-contact"
                                                                          : "new";
      finding.kernel_dimension = KernelDimension(MatrixA(b, polished, period, seq), 1e-6);
      if (m % 2 == 0) ++report.kernel_dimension_histogram[finding.kernel_dimension];
      report.findings.push_back(finding);
    }
  }
  return report;
}

}  // namespace

long ExploreReport::Count(const std::string& kind, bool admissible_only) const {
  long n = 0;
  for (const ExploreFinding& f : findings) n += f.kind == kind && (!admissible_only || f.orbit.admissible);
  return n;
}

bool CoincidentImpacts(const std::vector<double>& times, double period, int impacts, const std::vector<int>& sequence,
                       bool same_contact) {
  NSMODAL_CHECK(static_cast<int>(times.size()) + 1 == impacts &&
                (sequence.empty() || static_cast<int>(sequence.size()) == impacts));
  std::vector<double> all{0.0};
  all.insert(all.end(), times.begin(), times.end());
  for (int i = 0; i < impacts; ++i) {
    const double next = i + 1 < impacts ? all[i + 1] : period;
    // (An empty sequence: every impact on contact 1.)
    const bool same = sequence.empty() || sequence[i] == sequence[(i + 1) % impacts];
    if (next - all[i] < 1e-6 * period && same == same_contact) return true;
  }
  return false;
}

ExploreReport ExploreImpacts(const AnalysisBasis& b, const std::vector<double>& periods, const ExploreOptions& options) {
  b.RequireElastic("the search for orbits of 3 to 6 impacts (explore)");
  if (options.impacts < 3 || options.impacts > 6) {
    throw InputError("impacts", "the exploratory search takes 3 to 6 impacts, got " +
                                    std::to_string(options.impacts));
  }
  if (options.grid < 4 || options.grid > 200) {
    throw InputError("grid", "must lie in [4, 200], got " + std::to_string(options.grid));
  }
  if (!options.sequence.empty()) {
    if (static_cast<int>(options.sequence.size()) != options.impacts) {
      throw InputError("sequence", "lists " + std::to_string(options.sequence.size()) + " impacts, but impacts is " +
                                       std::to_string(options.impacts));
    }
    for (int c : options.sequence) {
      if (c < 0 || c >= static_cast<int>(b.contacts.size())) {
        throw InputError("sequence", "names contact " + std::to_string(c + 1) + ", but the model has " +
                                         std::to_string(b.contacts.size()) + " contact(s)");
      }
    }
  }
  for (double period : periods) b.CheckPeriod(period);
  // The work, bounded before it starts (issue 29): each period samples the
  // C(grid - 1, m - 1) ordered impact times of the grid (and keeps them all
  // to rank them), each sample a kernel of the 2N x 2N map A_m: about 3.3e-5
  // s at N = 2 (the quick start's 19,987 samples of m = 3, grid 24, 79
  // periods: 0.67 s on one core), growing as N^3. m = 6 at grid 200 asks
  // 2.5e9 samples a period (and ~100 GB to rank them): beyond kMaxSamples
  // sample-units (2 minutes, ~200 MB of ranking at N = 2) it is refused.
  constexpr double kMaxSamples = 4e6;
  double per_period = 1.0;
  for (int i = 1; i <= options.impacts - 1; ++i) per_period = per_period * (options.grid - i) / i;
  const double n_scale = std::max(1.0, std::pow(b.n / 2.0, 3));
  const double work = per_period * static_cast<double>(periods.size()) * n_scale;
  if (work > kMaxSamples) {
    throw InputError("grid", FormatValue(per_period) + " samples a period (C(grid - 1, m - 1), grid " +
                                 std::to_string(options.grid) + ", m = " + std::to_string(options.impacts) + ") over " +
                                 std::to_string(periods.size()) + " periods" +
                                 (n_scale > 1.0 ? ", times " + FormatValue(n_scale) + " for N = " + std::to_string(b.n)
                                                : std::string()) +
                                 ": " + FormatValue(work) + " sample-units, beyond the limit of " +
                                 FormatValue(kMaxSamples) + ": use a coarser --grid, fewer periods or fewer impacts");
  }
  // Periods are independent: searched in parallel, merged in their order.
  std::vector<ExploreReport> parts(periods.size());
  ParallelFor(
      static_cast<long>(periods.size()), options.threads,
      [&](long i) { parts[i] = ExploreOnePeriod(b, periods[i], options); }, options.progress);
  ExploreReport report;
  report.impacts = options.impacts;
  report.best_phi_new = std::numeric_limits<double>::infinity();
  for (const ExploreReport& p : parts) {
    report.samples += p.samples;
    for (auto [k, v] : p.kernel_dimension_histogram) report.kernel_dimension_histogram[k] += v;
    report.findings.insert(report.findings.end(), p.findings.begin(), p.findings.end());
    report.best_phi_new = std::min(report.best_phi_new, p.best_phi_new);
  }
  return report;
}

}  // namespace nsmodal

namespace nsmodal {
namespace {

// Converged: every |c_i / c_0 - 1| at most this (round-off of the SVD kernel
// and of the flows, measured ~1e-14 on the paper's 3-ipp family).
constexpr double kFamilyTol = 1e-12;

// NC2 of an odd-m orbit at (times, T): r_i = c_i / c_0 - 1, i = 1..m-1, with c
// the x_c of the kernel vector at the impacts; y0 = y d / c_0. False outside
// the domain (times out of order, c_0 = 0).
bool OddResidual(const AnalysisBasis& b, const std::vector<double>& times, double period,
                 const std::vector<int>& sequence, Eigen::VectorXd& r, Eigen::VectorXd* y0 = nullptr) {
  KernelContacts kc;
  if (!KernelAtImpacts(b, times, period, 1, kc, sequence)) return false;
  const long m = kc.c.rows();
  // c_i / d_{j_i}: each impact on its own wall (all d: one contact).
  const Eigen::VectorXd d = Gaps(b, sequence, static_cast<int>(m));
  const bool one_wall = std::all_of(sequence.begin(), sequence.end(), [](int j) { return j == 0; });
  const Eigen::VectorXd c = one_wall ? Eigen::VectorXd(kc.c.col(0)) : Eigen::VectorXd(kc.c.col(0).cwiseQuotient(d));
  if (!(std::abs(c[0]) > 0.0)) return false;
  r = c.tail(m - 1) / c[0] - Eigen::VectorXd::Ones(m - 1);
  if (y0 != nullptr) *y0 = kc.basis.col(0) * ((one_wall ? b.gap : 1.0) / c[0]);
  return r.allFinite();
}

// Newton on the impact times at a fixed period.
std::optional<std::vector<double>> CorrectTimes(const AnalysisBasis& b, std::vector<double> times, double period,
                                                const std::vector<int>& sequence) {
  const int k = static_cast<int>(times.size());
  Eigen::VectorXd r(k), rh(k);
  for (int it = 0; it <= 30; ++it) {
    if (!OddResidual(b, times, period, sequence, r)) return std::nullopt;
    if (r.cwiseAbs().maxCoeff() <= kFamilyTol) return times;
    if (it == 30) break;
    Eigen::MatrixXd jac(k, k);
    const double h = 1e-7 * period;
    for (int j = 0; j < k; ++j) {
      std::vector<double> tp = times;
      tp[j] += h;
      if (!OddResidual(b, tp, period, sequence, rh)) return std::nullopt;
      jac.col(j) = (rh - r) / h;
    }
    const Eigen::VectorXd dx = jac.fullPivLu().solve(-r);
    if (!dx.allFinite()) return std::nullopt;
    for (int j = 0; j < k; ++j) times[j] += dx[j];
  }
  return std::nullopt;
}

// The times at T on the line through two points of the family.
std::vector<double> Interpolate(const Orbit& a, const Orbit& b, double period) {
  std::vector<double> t(a.times.size());
  const double s = (period - a.period) / (b.period - a.period);
  for (std::size_t i = 0; i < t.size(); ++i) t[i] = a.times[i] + s * (b.times[i] - a.times[i]);
  return t;
}

std::optional<Orbit> FamilyOrbit(const AnalysisBasis& b, const std::vector<double>& guess, double period,
                                 const std::vector<int>& sequence) {
  const std::optional<std::vector<double>> times = CorrectTimes(b, guess, period, sequence);
  if (!times) return std::nullopt;
  Eigen::VectorXd r, y0;
  OddResidual(b, *times, period, sequence, r, &y0);
  return EvaluateOrbit(b, y0, *times, period, {}, sequence);
}

}  // namespace

Family FollowOddImpactFamily(const AnalysisBasis& b, const Orbit& start, double to, const FamilyOptions& options) {
  b.RequireElastic("the odd-m family continuation");
  const int m = start.impacts;
  if (m % 2 == 0 || m < 3 || m > 5 || static_cast<int>(start.times.size()) != m - 1) {
    throw InputError("impacts", "the family continuation takes an orbit with 3 or 5 impacts (odd m: a one-"
                                "dimensional kernel), got " + std::to_string(m));
  }
  b.CheckPeriod(start.period, "period");
  b.CheckPeriod(to, "period");
  if (!(options.step > 0.0) || !std::isfinite(options.step)) {
    throw InputError("step", "must be positive and finite, got " + FormatValue(options.step));
  }
  Family f;
  f.admissibility_change = std::numeric_limits<double>::quiet_NaN();
  f.orbits.push_back(start);
  const double dir = to >= start.period ? 1.0 : -1.0;
  double h = options.step;
  int halvings = 0;
  bool after_jump = false;
  while (true) {
    ThrowIfStopRequested();
    const Orbit& cur = f.orbits.back();
    if (std::abs(to - cur.period) <= 1e-12 * std::abs(to)) {
      f.stop = "reached T = " + FormatValue(to);
      break;
    }
    if (static_cast<long>(f.orbits.size()) >= options.max_points) {
      f.stop = "point limit " + std::to_string(options.max_points) + " reached at T = " + FormatValue(cur.period);
      break;
    }
    const double period = cur.period + dir * std::min(h, std::abs(to - cur.period));
    std::vector<double> guess = cur.times;
    if (f.orbits.size() >= 2) {
      guess = Interpolate(f.orbits[f.orbits.size() - 2], cur, period);
    } else {
      for (double& t : guess) t *= period / cur.period;
    }
    const std::optional<Orbit> next = FamilyOrbit(b, guess, period, start.sequence);
    // A correction ten times the step's prediction (or the step) has landed
    // on another branch: past a fold of the family, Newton converges to
    // another root (on paper.toml's 3-ipp family the impact times jumped by
    // a fifteenth of the period).
    double moved = 0.0, predicted = 0.0;
    for (std::size_t i = 0; next && i < guess.size(); ++i) {
      moved = std::max(moved, std::abs(next->times[i] - guess[i]));
      predicted = std::max(predicted, std::abs(guess[i] - cur.times[i]));
    }
    const bool jumped = next && moved > 10.0 * std::max(predicted, h);
    if (!next || jumped) {
      // (Past a fold where the family turns back in T every step fails or
      // jumps: the end is located to 1e-7 T.)
      after_jump = jumped;
      if (++halvings > 30 || h < 1e-7 * std::abs(cur.period)) {
        f.stop = jumped ? "the continuation in T lands on another branch beyond T = " : "Newton does not converge beyond T = ";
        f.stop += FormatValue(cur.period);
        f.stop += halvings > 30 ? " (30 step halvings)" : " (the step halved below 1e-7 T)";
        break;
      }
      h *= 0.5;
      continue;
    }
    halvings = 0;
    // (Not after a jump: the step that landed would jump again.)
    if (!after_jump) h = std::min(options.step, 2.0 * h);
    after_jump = false;
    f.orbits.push_back(*next);
    const Orbit& a = f.orbits[f.orbits.size() - 2];
    const Orbit& z = f.orbits.back();
    if (std::isnan(f.admissibility_change) && a.admissible != z.admissible) {
      // Bisection in T, each point corrected from the line through a and z.
      Orbit lo = a, hi = z;
      for (int it = 0; it < 60 && std::abs(hi.period - lo.period) > 1e-12 * std::abs(lo.period); ++it) {
        const double mid = 0.5 * (lo.period + hi.period);
        const std::optional<Orbit> o = FamilyOrbit(b, Interpolate(a, z, mid), mid, start.sequence);
        if (!o) break;
        (o->admissible == a.admissible ? lo : hi) = *o;
      }
      f.admissibility_change = 0.5 * (lo.period + hi.period);
      f.at_change = lo;
    }
    if (!z.potential) {
      f.stop = "not potential at T = " + FormatValue(z.period) + ": " + z.reason;
      break;
    }
  }
  return f;
}

FamilyStretch FollowOddImpactFamilyBothWays(const AnalysisBasis& b, const Orbit& start, double from, double to,
                                            const FamilyOptions& options) {
  FamilyStretch f;
  f.down = FollowOddImpactFamily(b, start, from, options);
  f.up = FollowOddImpactFamily(b, start, to, options);
  auto end = [](const Family& fam) {
    return std::isnan(fam.admissibility_change) ? fam.orbits.back().period : fam.admissibility_change;
  };
  f.from = end(f.down);
  f.to = end(f.up);
  return f;
}

void CheckFamilyRange(const AnalysisBasis& b, int impacts, double from, double to, const FieldNames& names) {
  if (impacts % 2 == 0) {
    throw InputError(names("follow"), "follows families with an odd number of impacts (3 or 5), got " +
                                          names("impacts") + " " + std::to_string(impacts));
  }
  b.CheckPeriod(from, names("follow"));
  b.CheckPeriod(to, names("follow"));
}

std::vector<FamilySummary> FollowNewFamilies(const AnalysisBasis& b, const ExploreReport& report, double from,
                                             double to, const FamilyOptions& options) {
  std::vector<FamilySummary> out;
  for (const ExploreFinding& f : report.findings) {
    if (f.kind != "new" || !f.orbit.admissible) continue;
    const FamilyStretch fam = FollowOddImpactFamilyBothWays(b, f.orbit, from, to, options);
    const double lo = fam.from, hi = fam.to;
    bool seen = false;
    for (const FamilySummary& s : out) {
      seen = seen || (std::abs(s.from - lo) <= 1e-9 * hi && std::abs(s.to - hi) <= 1e-9 * hi);
    }
    if (seen) continue;
    FamilySummary s;
    s.start = f.orbit;
    s.from = lo;
    s.to = hi;
    if (std::isnan(fam.down.admissibility_change)) s.lower_end = fam.down.stop;
    if (std::isnan(fam.up.admissibility_change)) s.upper_end = fam.up.stop;
    for (const Orbit& o : fam.Ascending()) {  // the start once (it was counted in both directions)
      if (!o.admissible) continue;
      ++s.points;
      s.energy_min = std::min(s.energy_min, o.energy);
      s.energy_max = std::max(s.energy_max, o.energy);
      const Stability st = OrbitStability(b, o);
      if (st.defined) {
        s.multiplier_min = std::min(s.multiplier_min, st.max_modulus);
        s.multiplier_max = std::max(s.multiplier_max, st.max_modulus);
      }
    }
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<Orbit> FamilyStretch::Ascending() const {
  std::vector<Orbit> out(down.orbits.rbegin(), down.orbits.rend());
  out.insert(out.end(), up.orbits.begin() + 1, up.orbits.end());
  return out;
}

}  // namespace nsmodal
