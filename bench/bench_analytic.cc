// Benchmarks of the analytic engine against the targets of issue 2, on one core:
//   1-ipp sweep of 100,000 periods with the exact NC3 check     <= 1 s
//   2-ipp roots for T in (0, 40] at step 0.01                    <= 10 s
// with the accuracy reached reported as counters:
//   worst periodicity residual |z(T) - z(0)| / |z(0)|            <= 1e-12
//   2-ipp roots: largest change when the t2 grid is refined 10x  <= 1e-10
//   transitions: largest change when the T grid is refined 7.7x  <= 1e-9
// and, for issue 5 (no targets given; cost and accuracy reported):
//   the three bridges on (0, 40]: cost, worst NC2 degeneracy residual;
//   continuation of the 2-ipp branch through 3 T1: cost per point, worst
//   sigma_min(A_2) along it (how far the points are from exact roots);
// and for issue 11: a frequency-response curve of the paper's system
// (configs/forced.toml) over 300 frequencies, stability included, <= 1 s,
// through at least one fold; its worst residual and energy-balance error.
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "nsmodal/atlas.h"
#include "nsmodal/bridge.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/curve.h"
#include "nsmodal/response.h"
#include "nsmodal/scene.h"
#include "nsmodal/return_map.h"
#include "nsmodal/transitions.h"
#include "nsmodal/two_impact.h"

namespace nsmodal {
namespace {

void BM_OneImpactSweep100k(benchmark::State& state) {
  const AnalysisBasis b(PaperModel());
  double worst = 0.0;
  long admissible = 0;
  for (auto _ : state) {
    worst = 0.0;
    admissible = 0;
    for (int k = 1; k <= 100000; ++k) {
      const Orbit o = OneImpactOrbit(b, 4e-4 * k);
      if (o.potential) worst = std::max(worst, o.periodicity_residual);
      admissible += o.admissible;
    }
  }
  state.counters["worst_periodicity_residual"] = worst;
  state.counters["admissible"] = static_cast<double>(admissible);
}
BENCHMARK(BM_OneImpactSweep100k)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_TwoImpactRootsTo40(benchmark::State& state) {
  const AnalysisBasis b(PaperModel());
  long roots = 0;
  double worst = 0.0;
  for (auto _ : state) {
    roots = 0;
    worst = 0.0;
    for (int k = 1; k <= 4000; ++k) {
      for (const Orbit& o : TwoImpactOrbits(b, 0.01 * k)) {
        ++roots;
        if (o.potential) worst = std::max(worst, o.periodicity_residual);
      }
    }
  }
  state.counters["roots"] = static_cast<double>(roots);
  state.counters["worst_periodicity_residual"] = worst;
}
BENCHMARK(BM_TwoImpactRootsTo40)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_TwoImpactRootAccuracy(benchmark::State& state) {
  // Root accuracy, independently of how the roots were found: sigma_min(A_2)
  // at every root of 200 periods (0 at an exact root, ~1e-15 at round-off).
  const AnalysisBasis b(PaperModel());
  double worst = 0.0;
  long roots = 0;
  for (auto _ : state) {
    for (int k = 1; k <= 200; ++k) {
      const double period = 0.2 * k;
      for (double t2 : TwoImpactRoots(b, period)) {
        ++roots;
        worst = std::max(worst, TwoImpactKernelResidual(b, t2, period));
      }
    }
  }
  state.counters["roots"] = static_cast<double>(roots);
  state.counters["worst_sigma_min"] = worst;
}
BENCHMARK(BM_TwoImpactRootAccuracy)->Unit(benchmark::kMillisecond)->Iterations(1);

// Issue 12, large systems (chains of unit masses and springs, contact on the
// last mass, both cores):
//   1-ipp sweep T = 0.5:60:0.01 (5,951 periods) with every potential orbit's
//   stability: N = 100 <= 3 s and <= 200 MB; N = 1,000 <= 60 s;
//   2-ipp sweep T = 2:30:0.1 with stability: N = 10 <= 2 s.
// Arguments: N, then 1 for every multiplier or 0 for the verdict only (the
// largest modulus and the multipliers off the unit circle). Run one at a time
// (--benchmark_filter) for a meaningful peak memory (rss_mb is the process's).
Model UnitChain(int n) {
  return MakeChain(std::vector<double>(static_cast<std::size_t>(n), 1.0), std::vector<double>(static_cast<std::size_t>(n), 1.0),
                   n - 1, 1.0, 1.0);
}

void ChainSweep(benchmark::State& state, int impacts, const PeriodGrid& grid) {
  const AnalysisBasis b(UnitChain(static_cast<int>(state.range(0))));
  SweepOptions opt;
  opt.stability = StabilityPolicy::kPotential;
  opt.stability_options.all_multipliers = state.range(1) != 0;
  long orbits = 0, admissible = 0, stable = 0, fallback = 0;
  double worst = 0.0;
  for (auto _ : state) {
    orbits = admissible = stable = fallback = 0;
    worst = 0.0;
    StreamSweep(b, grid, impacts, opt, [&](double, std::vector<OrbitRecord>& list) {
      for (const OrbitRecord& r : list) {
        ++orbits;
        admissible += r.orbit.admissible;
        stable += r.stable();
        fallback += r.stability && r.stability->dense_fallback;
        if (r.orbit.potential) worst = std::max(worst, r.orbit.periodicity_residual);
      }
    });
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  state.counters["orbits"] = static_cast<double>(orbits);
  state.counters["admissible"] = static_cast<double>(admissible);
  state.counters["stable"] = static_cast<double>(stable);
  state.counters["dense_fallbacks"] = static_cast<double>(fallback);
  state.counters["worst_periodicity_residual"] = worst;
  state.counters["rss_mb"] = static_cast<double>(usage.ru_maxrss) / 1024.0;
}

void BM_ChainOneImpactSweep(benchmark::State& state) { ChainSweep(state, 1, PeriodGrid{0.5, 60.0, 0.01}); }
BENCHMARK(BM_ChainOneImpactSweep)
    ->Args({10, 1})
    ->Args({100, 1})
    ->Args({100, 0})
    ->Args({1000, 0})
    ->Args({1000, 1})
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1);

void BM_ChainTwoImpactSweep(benchmark::State& state) { ChainSweep(state, 2, PeriodGrid{2.0, 30.0, 0.1}); }
BENCHMARK(BM_ChainTwoImpactSweep)->Args({10, 1})->Args({100, 1})->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

// Issue 24, several contacts: the paper's chain between two stops (x2 <= 1,
// x2 >= -1.2: configs/clearance.toml), the family of the impact sequence
// (1, 2) over T = 2:27:0.005 (5,001 periods) with every potential orbit's
// stability, on one core (arg 1) and on both (arg 0: all cores). Target:
// under 1 s.
// The family of the sequence (1, 2) of `b` over `grid`, with every potential
// orbit's stability, and its counts.
void SequenceSweep(benchmark::State& state, const AnalysisBasis& b, const PeriodGrid& grid, int threads) {
  SweepOptions opt;
  opt.stability = StabilityPolicy::kPotential;
  opt.sequence = {0, 1};
  opt.threads = threads;
  long orbits = 0, admissible = 0, stable = 0;
  for (auto _ : state) {
    orbits = admissible = stable = 0;
    StreamSweep(b, grid, 2, opt, [&](double, std::vector<OrbitRecord>& list) {
      for (const OrbitRecord& r : list) {
        ++orbits;
        admissible += r.orbit.admissible;
        stable += r.stable();
      }
    });
  }
  state.counters["periods"] = static_cast<double>(grid.Count());
  state.counters["orbits"] = static_cast<double>(orbits);
  state.counters["admissible"] = static_cast<double>(admissible);
  state.counters["stable"] = static_cast<double>(stable);
}

void BM_TwoContactSweep(benchmark::State& state) {
  Model m = PaperModel();
  m.contacts = {DofContact(2, 1, true, 1.0, 1.0), DofContact(2, 1, false, 1.2, 1.0)};
  SequenceSweep(state, AnalysisBasis(m), PeriodGrid{2.0, 27.0, 0.005}, static_cast<int>(state.range(0)));
}
BENCHMARK(BM_TwoContactSweep)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// The conservative impact damper (configs/impact-damper-free.toml: a free
// mass, a rigid-body mode), its (1, 2) family over T = 2:52:0.01 (5,001
// periods) with every potential orbit's stability, on one core.
void BM_FreeDamperSweep(benchmark::State& state) {
  Model m;
  m.mass = Eigen::Vector2d(1.0, 0.1).asDiagonal();
  m.stiffness = Eigen::Matrix2d::Zero();
  m.stiffness(0, 0) = 1.0;
  m.contacts = {BetweenContact(2, 1, 0, 0.5, 1.0), BetweenContact(2, 0, 1, 0.5, 1.0)};
  SequenceSweep(state, AnalysisBasis(m), PeriodGrid{2.0, 52.0, 0.01}, 1);
}
BENCHMARK(BM_FreeDamperSweep)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

void BM_TransitionsTo40(benchmark::State& state) {
  const AnalysisBasis b(PaperModel());
  double worst = 0.0;
  long count = 0;
  for (auto _ : state) {
    const std::vector<Transition> a = OneImpactTransitions(b, 0.05, 40.0, 0.01);
    const std::vector<Transition> c = OneImpactTransitions(b, 0.05, 40.0, 0.0013);
    count = static_cast<long>(a.size());
    if (a.size() != c.size()) worst = INFINITY;
    for (std::size_t i = 0; i < std::min(a.size(), c.size()); ++i)
      worst = std::max(worst, std::abs(a[i].period - c[i].period));
  }
  state.counters["transitions"] = static_cast<double>(count);
  state.counters["worst_location_change"] = worst;
}
BENCHMARK(BM_TransitionsTo40)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_BridgesTo40(benchmark::State& state) {
  const AnalysisBasis b(PaperModel());
  std::vector<double> grazing;
  for (const Transition& t : OneImpactTransitions(b, 0.05, 40.0, 0.01)) {
    if (t.kind == TransitionKind::kGrazing) grazing.push_back(t.period);
  }
  double worst = 0.0;
  for (auto _ : state) {
    for (double tg : grazing) worst = std::max(worst, BridgeAt(b, tg).degeneracy_residual);
  }
  state.counters["bridges"] = static_cast<double>(grazing.size());
  state.counters["worst_degeneracy_residual"] = worst;
}
BENCHMARK(BM_BridgesTo40)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_TwoImpactContinuation(benchmark::State& state) {
  const AnalysisBasis b(PaperModel());
  const double t1 = b.Periods().minCoeff();
  BranchOptions opt;
  opt.step = 2e-3 * 3 * t1;
  opt.period_min = 1.5 * t1;
  opt.period_max = 4.5 * t1;
  std::vector<BranchPoint> branch;
  for (auto _ : state) branch = TwoImpactBranch(b, t1, 3 * t1, opt);
  double worst = 0.0;
  for (const BranchPoint& p : branch) {
    worst = std::max(worst, Eigen::JacobiSVD<Eigen::MatrixXd>(MatrixA(b, {p.t2}, p.period)).singularValues().minCoeff());
  }
  state.counters["points"] = static_cast<double>(branch.size());
  state.counters["worst_sigma_min"] = worst;
}
BENCHMARK(BM_TwoImpactContinuation)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_ResponseCurve300(benchmark::State& state) {
  const Model m = LoadScene(NSMODAL_SOURCE_DIR "/configs/forced.toml").model;
  ResponseOptions o;
  o.impacts = static_cast<int>(state.range(0));
  o.grid = {0.3, 3.29, 0.01};
  o.fixed = 0.3;
  ResponseCurve c;
  for (auto _ : state) c = ComputeResponse(m, o);
  long points = 0, folds = 0;
  double residual = 0.0, balance = 0.0;
  for (const ResponseBranch& b : c.branches) {
    points += static_cast<long>(b.points.size());
    for (const ForcedOrbit& p : b.points) {
      residual = std::max(residual, p.residual);
      balance = std::max(balance, std::abs(p.work - p.dissipated - p.impact_loss) / std::abs(p.work));
    }
  }
  for (const SpecialPoint& p : c.points) folds += p.kind == SpecialKind::kFold ? 1 : 0;
  state.counters["frequencies"] = static_cast<double>(o.grid.Count());
  state.counters["points"] = static_cast<double>(points);
  state.counters["branches"] = static_cast<double>(c.branches.size());
  state.counters["folds"] = static_cast<double>(folds);
  state.counters["worst_residual"] = residual;
  state.counters["worst_balance"] = balance;
}
BENCHMARK(BM_ResponseCurve300)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->Iterations(1);

// Issue 26's target: a 300-step continuation of configs/forced.toml's (1,1)
// response (the paper's chain, 2 % damping, e = 0.8) in the forcing
// amplitude (arg 0: a in [0.05, 0.5] at w = 0.5) or in the gap (arg 1: d in
// [0.5, 2], the model rebuilt at each value), stability and special points
// included: under 1 s.
void BM_Continuation300(benchmark::State& state) {
  const Model m = LoadScene(NSMODAL_SOURCE_DIR "/configs/forced.toml").model;
  const bool gap = state.range(0) == 1;
  const ResponseRequest r = MakeContinuationRequest(m, gap ? "gap" : "amplitude", gap ? "0.5:2" : "0.05:0.5", 1, 1);
  ResponseLevels c;
  for (auto _ : state) c = ComputeResponseLevels(m, r.options, r.levels);
  double residual = 0.0;
  for (const ResponseRow& row : c.rows) residual = std::max(residual, row.orbit.residual);
  state.counters["steps"] = static_cast<double>(r.options.grid.Count() - 1);
  state.counters["points"] = static_cast<double>(c.rows.size());
  state.counters["special_points"] = static_cast<double>(c.points.size());
  state.counters["worst_residual"] = residual;
}
BENCHMARK(BM_Continuation300)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// Issue 26's target: the grazing curves of the (1,1) response of
// configs/forced.toml in (frequency, amplitude) over w in [0.3, 1.2] (a in
// [0.05, 1]) under 5 s, every point to 1e-10 in its defining condition
// (max_interior_gap / d): worst_condition.
void BM_GrazingCurve(benchmark::State& state) {
  const Model m = LoadScene(NSMODAL_SOURCE_DIR "/configs/forced.toml").model;
  const CurveOptions o = MakeCurveRequest(m, "frequency", "0.3:1.2", "amplitude", "0.05:1", "grazing", 1, 1);
  CurveSet s;
  for (auto _ : state) s = FollowCurves(m, o);
  double worst = 0.0;
  long points = 0;
  for (const CurvePoint& p : s.rows) {
    if (p.kind != "grazing") continue;
    ++points;
    worst = std::max(worst, p.condition ? std::abs(*p.condition) : std::numeric_limits<double>::infinity());
  }
  state.counters["curves"] = s.curves;
  state.counters["points"] = static_cast<double>(points);
  state.counters["worst_condition"] = worst;
}
BENCHMARK(BM_GrazingCurve)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace
}  // namespace nsmodal

BENCHMARK_MAIN();
