#include "nsmodal/figure_subjects.h"

#include <algorithm>
#include <cmath>

#include "nsmodal/admissibility.h"
#include "nsmodal/check.h"
#include "nsmodal/error.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/two_impact.h"

namespace nsmodal {

PeriodGrid FiguresGrid(const AnalysisBasis& b, const std::optional<std::string>& text, const std::string& field) {
  const double step = 0.01;
  // (4 times the longest elastic period: a rigid-body mode's is infinite.)
  const std::string range = text ? *text
                                 : FormatValue(step) + ":" +
                                       FormatValue(std::ceil(4.0 * b.Periods().tail(b.n - b.rigid).maxCoeff())) + ":" +
                                       FormatValue(step);
  const PeriodGrid grid = PeriodGrid::Parse(range, field);
  if (grid.Count() < 2) throw InputError(field, "needs at least two periods, got '" + range + "'");
  CheckSweepWork(b, grid, {1, 2}, field, true);
  return grid;
}

bool AtHalfPeriod(double t, double period) { return std::abs(t - 0.5 * period) <= 1e-9 * period; }
bool IsHalfPeriodRoot(const Orbit& o) { return AtHalfPeriod(o.times[0], o.period); }
bool IsGrazing(const Bridge& br) { return br.kind == BridgeKind::kGrazing; }
bool GrazesAtHalfPeriod(const Bridge& br) { return AtHalfPeriod(br.t2, br.period); }

Orbit GrazingMode(const AnalysisBasis& b, int mode, double period) {
  Eigen::VectorXd y = Eigen::VectorXd::Zero(2 * b.n);
  y[mode] = b.gap / b.r_over_omega[mode];
  return EvaluateOrbit(b, y, {}, period);
}

int ModeOf(const AnalysisBasis& b, double period) {
  const Eigen::VectorXd ti = b.Periods();
  int best = 0;
  double err = INFINITY;
  for (int i = 0; i < b.n; ++i) {
    const double k = std::round(period / ti[i]);
    const double e = std::abs(period - k * ti[i]);
    if (k >= 1 && e < err) {
      err = e;
      best = i;
    }
  }
  return best;
}

std::optional<Orbit> KernelMotionOffTheObstacle(const AnalysisBasis& b, const Orbit& potential, double at_t2) {
  NSMODAL_CHECK(potential.impacts == 2 && at_t2 != b.gap);
  // Conditions within 1e-8 of dependent (a bridge, where x_c(0) = d fixes
  // x_c(t2)) would amplify round-off by 1e8: no figure.
  std::optional<Orbit> o = TwoImpactKernelOrbit(b, potential.times[0], potential.period, at_t2, 1e-8);
  if (o && !(o->max_excess > 0.0)) return std::nullopt;
  return o;
}

std::optional<Orbit> NotAdmissibleExample(const AnalysisBasis& b, const Atlas& atlas) {
  for (const auto& list : atlas.two.at) {
    for (const OrbitRecord& r : list) {
      if (!r.orbit.potential || IsHalfPeriodRoot(r.orbit)) continue;
      const std::optional<Orbit> m = KernelMotionOffTheObstacle(b, r.orbit, 0.5 * b.gap);
      if (m && m->max_excess > 0.05 * b.gap && m->max_excess < b.gap) return m;
    }
  }
  return std::nullopt;
}

ModalPick PickModalTransition(const AnalysisBasis& b, const Atlas& atlas) {
  const Eigen::VectorXd ti = b.Periods();
  // The zones' ends only: a stability change inside a zone is not its edge.
  std::vector<Transition> tr;
  for (const Transition& t : atlas.transitions) {
    if (BoundsAZone(t.kind)) tr.push_back(t);
  }
  const std::vector<double>& periods = atlas.one.periods;
  ModalPick first;
  for (std::size_t k = 0; k < tr.size(); ++k) {
    const Transition& t = tr[k];
    if (t.kind != TransitionKind::kModal) continue;
    const double eps = 1e-4 * t.period;
    const int side = OneImpactOrbit(b, t.period + eps).admissible   ? 1
                     : OneImpactOrbit(b, t.period - eps).admissible ? -1
                                                                     : 0;
    if (side == 0) continue;
    const double neighbour = side > 0 ? (k + 1 < tr.size() ? tr[k + 1].period : periods.back())
                                      : (k > 0 ? tr[k - 1].period : periods.front());
    const ModalPick p{t.period, side, std::abs(neighbour - t.period)};
    if (t.period > 1.5 * ti[ModeOf(b, t.period)]) return p;
    if (first.side == 0) first = p;
  }
  return first;
}

const Bridge* PaperBridge(const Atlas& atlas) {
  const Bridge* first = nullptr;
  for (const Bridge& br : atlas.bridges) {
    if (!IsGrazing(br)) continue;
    if (GrazesAtHalfPeriod(br)) return &br;
    if (!first) first = &br;
  }
  return first;
}

std::optional<TwoGrazes> TwoGrazesExample(const AnalysisBasis& b, const Atlas& atlas) {
  for (const Bridge& br : atlas.bridges) {
    if (!IsGrazing(br) || GrazesAtHalfPeriod(br)) continue;
    Orbit three = EvaluateOrbit(b, br.origin, {br.t2, br.period - br.t2}, br.period);
    if (!three.admissible) continue;
    return TwoGrazes{&br, OneImpactOrbit(b, br.period), std::move(three)};
  }
  return std::nullopt;
}

ModeBranch TwoImpactModeBranch(const AnalysisBasis& b) {
  ModeBranch m;
  const Eigen::VectorXd ti = b.Periods();
  for (int i = 0; i < b.n; ++i) {
    if (std::abs(b.r[i]) > 0.0 && ti[i] < ti[m.mode]) m.mode = i;
  }
  m.period = 3.0 * ti[m.mode];
  m.t2 = ti[m.mode];
  BranchOptions opt;
  opt.step = 2e-3 * m.period;
  opt.period_min = 0.5 * m.period;
  opt.period_max = 1.5 * m.period;
  if (!(TwoImpactKernelResidual(b, m.t2, m.period) < opt.kernel_tol)) {
    m.why_not = "(t2, T) = (" + FormatValue(m.t2) + ", " + FormatValue(m.period) + ") is not a root of det A_2";
    return m;
  }
  m.branch = TwoImpactBranch(b, m.t2, m.period, opt);
  std::size_t start = 0;
  while (start < m.branch.size() && m.branch[start].arclength < 0.0) ++start;
  auto admissible = [&](std::size_t k) { return TwoImpactOrbitAt(b, m.branch[k].t2, m.branch[k].period).admissible; };
  for (int dir : {1, -1}) {
    std::vector<std::size_t> side;
    for (long k = static_cast<long>(start) + dir; k >= 0 && k < static_cast<long>(m.branch.size()); k += dir) {
      if (!admissible(static_cast<std::size_t>(k))) break;
      side.push_back(static_cast<std::size_t>(k));
    }
    if (side.size() > m.run.size()) m.run = side;
  }
  if (m.run.empty()) m.why_not = "no admissible 2-ipp orbit next to the mode at T = " + FormatValue(m.period);
  return m;
}

ThreeImpactPick ThreeImpactFamilyExample(const AnalysisBasis& b, const Atlas& atlas) {
  ThreeImpactPick pick;
  const double last = atlas.one.periods.back(), first = atlas.one.periods.front();
  const double spacing = std::max(1.0, last / 100.0);
  std::vector<double> periods;
  for (double t = spacing; t <= last; t += spacing) periods.push_back(t);
  if (periods.empty()) {
    pick.why_not = "the atlas ends before T = 1";
    return pick;
  }
  ExploreOptions opt;
  opt.impacts = 3;
  const ExploreReport report = ExploreImpacts(b, periods, opt);
  FamilyOptions fo;
  fo.step = atlas.grid.step;
  // Preferred: a family that ends on a grazing 1-ipp orbit (one of its
  // impacts becoming the graze: where it meets the 1-ipp family), then the
  // longest admissible stretch.
  auto ends_on_graze = [&](double lo, double hi) {
    for (const Transition& t : atlas.transitions) {
      if (t.kind != TransitionKind::kGrazing) continue;
      if (std::abs(lo - t.period) <= 1e-6 * t.period || std::abs(hi - t.period) <= 1e-6 * t.period) return true;
    }
    return false;
  };
  bool best_on_graze = false;
  double best = -1.0;
  for (const ExploreFinding& f : report.findings) {
    if (f.kind != "new" || !f.orbit.admissible) continue;
    const FamilyStretch fam = FollowOddImpactFamilyBothWays(b, f.orbit, std::max(first, 0.5 * f.orbit.period),
                                                            std::min(last, 2.0 * f.orbit.period), fo);
    const double lo = fam.from, hi = fam.to;
    const bool on_graze = ends_on_graze(lo, hi);
    if (best_on_graze && !on_graze) continue;
    if (on_graze == best_on_graze && !(hi - lo > best)) continue;
    best_on_graze = on_graze;
    best = hi - lo;
    pick.start = f.orbit;
    pick.admissible_from = lo;
    pick.admissible_to = hi;
    pick.family = fam.Ascending();
  }
  if (pick.family.empty()) pick.why_not = "no admissible 3-ipp orbit that is not a lower-m orbit found";
  return pick;
}

}  // namespace nsmodal
