#include "nsmodal/transitions.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "nsmodal/admissibility.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/roots.h"
#include "nsmodal/stability.h"
#include "nsmodal/work.h"

namespace nsmodal {

std::string ToString(TransitionKind kind) {
  switch (kind) {
    case TransitionKind::kSingular: return "singular";
    case TransitionKind::kModal: return "modal";
    case TransitionKind::kGrazing: return "grazing";
    case TransitionKind::kMultiplierPlusOne: return "multiplier+1";
    case TransitionKind::kMultiplierMinusOne: return "multiplier-1";
  }
  return "?";
}

std::vector<double> ModalPeriods(const AnalysisBasis& b, double from, double to, int contact) {
  b.RequireElastic("the modal transitions of 1-impact families");
  const ModalContact& c = b.contacts[contact];
  std::vector<double> out;
  const Eigen::VectorXd periods = b.Periods();
  for (int i = 0; i < b.n; ++i) {
    if (std::abs(c.r[i]) < 1e-14 * std::sqrt(c.r_norm2)) continue;
    for (int k = std::max(1, static_cast<int>(std::ceil(from / periods[i]))); k * periods[i] <= to; ++k) {
      out.push_back(k * periods[i]);
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<double> SingularPeriods(const AnalysisBasis& b, double from, double to, int contact) {
  const ModalContact& c = b.contacts[contact];
  // Poles of D are the k T_i; D runs from +inf to -inf between consecutive poles.
  std::vector<double> poles{0.0};
  for (double p : ModalPeriods(b, 0.0, to, contact)) poles.push_back(p);
  const Eigen::VectorXd periods = b.Periods();
  double next = std::numeric_limits<double>::infinity();
  for (int i = 0; i < b.n; ++i) {
    if (std::abs(c.r[i]) >= 1e-14 * std::sqrt(c.r_norm2)) {
      next = std::min(next, (std::floor(to / periods[i]) + 1.0) * periods[i]);
    }
  }
  poles.push_back(next);
  std::sort(poles.begin(), poles.end());
  std::vector<double> out;
  auto d = [&b, contact](double t) { return SingularFunction(b, t, contact); };
  for (std::size_t k = 0; k + 1 < poles.size(); ++k) {
    const double lo = poles[k], hi = poles[k + 1];
    if (hi - lo <= 1e-12 * hi) continue;  // coincident poles (commensurate periods)
    // Step off the poles by a relative 1e-13: D there is ~1e13 in magnitude,
    // of the right sign, and Brent finds the single root inside. (Relative to
    // hi, not absolute: a bar's periods are ~1e-4 s, and an absolute 1e-13
    // crossed a pair of poles 1e-13 apart, a reversed bracket that reached
    // GSL's abort.)
    double a = lo + 1e-13 * hi, c = hi - 1e-13 * hi;
    if (!(d(a) > 0.0 && d(c) < 0.0)) continue;
    const double root = PolishRoot(d, a, c);
    if (root >= from && root <= to) out.push_back(root);
  }
  return out;
}

double GrazingFunction(const AnalysisBasis& b, double period, int contact) {
  const Orbit o = OneImpactOrbit(b, period, {}, contact);
  return CheckSegment(b, b.contacts[contact], o.y0, period).max_excess;
}

double OtherGrazingFunction(const AnalysisBasis& b, double period, int contact) {
  return OneImpactOrbit(b, period, {}, contact).other_excess;
}

std::vector<Transition> OneImpactTransitions(const AnalysisBasis& b, double from, double to, double step) {
  std::vector<double> periods;
  std::vector<bool> admissible;
  const long cells = std::lround(std::ceil((to - from) / step - 1e-9));
  for (long j = 0; j <= cells; ++j) {
    periods.push_back(std::min(to, from + j * step));
    admissible.push_back(OneImpactOrbit(b, periods.back()).admissible);
  }
  return OneImpactTransitions(b, periods, admissible);
}

std::vector<Transition> OneImpactTransitions(const AnalysisBasis& b, const std::vector<double>& periods,
                                             const std::vector<bool>& grid_admissible, int contact) {
  if (periods.size() < 2) return {};
  const double from = periods.front(), to = periods.back();
  // Bounded before it starts (work.h): the sweep's share is done, this is the search's.
  CheckSweepWork(b, from, (to - from) / static_cast<double>(periods.size() - 1), static_cast<long>(periods.size()), {},
                 "period", true);
  const std::vector<double> singular = SingularPeriods(b, from, to, contact);
  const std::vector<double> modal = ModalPeriods(b, from, to, contact);
  struct Special {
    double t;
    TransitionKind kind;
    int mode;
  };
  std::vector<Special> specials;
  for (double t : singular) specials.push_back({t, TransitionKind::kSingular, -1});
  const Eigen::VectorXd linear = b.Periods();
  for (double t : modal) {
    int mode = 0;
    for (int i = 0; i < b.n; ++i) {
      if (std::abs(std::remainder(t, linear[i])) < 1e-12 * t) mode = i;
    }
    specials.push_back({t, TransitionKind::kModal, mode});
  }
  std::sort(specials.begin(), specials.end(), [](const Special& x, const Special& y) { return x.t < y.t; });

  auto admissible = [&b, contact](double t) { return OneImpactOrbit(b, t, {}, contact).admissible; };
  std::vector<Transition> out;
  auto grazing = [&](double lo, double hi) {
    // h changes sign on [lo, hi]: polish the grazing period. Two special
    // periods closer than 2e-6 T (many modes: k T_i cluster) leave no room
    // between their probes.
    if (!(lo < hi)) return;
    auto h = [&b, contact](double t) { return GrazingFunction(b, t, contact); };
    if ((h(lo) > 0.0) != (h(hi) > 0.0)) {
      const double tg = PolishRoot(h, lo, hi);
      out.push_back({tg, TransitionKind::kGrazing, OneImpactOrbit(b, tg, {}, contact).energy, contact});
      return;
    }
    // Another contact's gap closing: where this family meets the families
    // that strike that contact too. Which contact grazes is read at the
    // polished period.
    if (b.contacts.size() < 2) return;
    auto g = [&b, contact](double t) { return OtherGrazingFunction(b, t, contact); };
    if ((g(lo) > 0.0) != (g(hi) > 0.0)) {
      const double tg = PolishRoot(g, lo, hi);
      const Orbit o = OneImpactOrbit(b, tg, {}, contact);
      out.push_back({tg, TransitionKind::kGrazing, o.energy, o.other_contact});
    }
  };
  bool adm_prev = grid_admissible[0];
  for (std::size_t j = 1; j < periods.size(); ++j) {
    const double ta = periods[j - 1];
    const double tb = periods[j];
    const bool adm_b = grid_admissible[j];
    std::vector<Special> inside;
    for (const Special& s : specials) {
      if (s.t > ta && s.t < tb) inside.push_back(s);
    }
    if (inside.empty()) {
      if (adm_prev != adm_b) grazing(ta, tb);
    } else {
      // Sub-intervals between the special periods, each side probed a relative
      // 1e-6 away: closer to a singular period the orbit's energy ~ 1/delta^2
      // makes x_c a cancellation of terms ~1/delta and NC2 fails on round-off.
      double left = ta;
      bool adm_left = adm_prev;
      for (const Special& s : inside) {
        const double delta = 1e-6 * s.t;
        const bool before = admissible(s.t - delta);
        const bool after = admissible(s.t + delta);
        if (adm_left != before) grazing(left, s.t - delta);
        if (before != after) {
          const double e = s.kind == TransitionKind::kSingular
                               ? std::numeric_limits<double>::infinity()
                               : 0.5 * std::pow(b.omega[s.mode] * b.contacts[contact].gap, 2) /
                                     (b.contacts[contact].r[s.mode] * b.contacts[contact].r[s.mode]);
          out.push_back({s.t, s.kind, e, contact});
        }
        left = s.t + delta;
        adm_left = after;
      }
      if (adm_left != adm_b) grazing(left, tb);
    }
    adm_prev = adm_b;
  }
  return out;
}

std::vector<Transition> OneImpactMultiplierCrossings(const AnalysisBasis& b, const std::vector<double>& periods,
                                                     const std::vector<bool>& admissible, int contact) {
  // Gt(2) and Gt(-2) on the grid, from one secular function per period.
  std::vector<double> plus(periods.size()), minus(periods.size());
  for (std::size_t j = 0; j < periods.size(); ++j) {
    const OneImpactSecular s = OneImpactSecularFunction(b, periods[j], contact);
    plus[j] = s.Value(2.0);
    minus[j] = s.Value(-2.0);
  }
  std::vector<Transition> out;
  for (const auto& [z, kind, g_grid] : {std::make_tuple(2.0, TransitionKind::kMultiplierPlusOne, &plus),
                                        std::make_tuple(-2.0, TransitionKind::kMultiplierMinusOne, &minus)}) {
    auto g = [&b, z = z, contact](double t) { return OneImpactSecularFunction(b, t, contact).Value(z); };
    for (std::size_t j = 1; j < periods.size(); ++j) {
      const double g_prev = (*g_grid)[j - 1], g_next = (*g_grid)[j];
      if (admissible[j - 1] && admissible[j] && std::isfinite(g_prev) && std::isfinite(g_next) &&
          (g_prev < 0.0) != (g_next < 0.0)) {
        const double t = PolishRoot(g, periods[j - 1], periods[j]);
        if (std::abs(g(t)) <= 1e-6 * (std::abs(g_prev) + std::abs(g_next))) {
          out.push_back({t, kind, OneImpactOrbit(b, t, {}, contact).energy, contact});
        }
      }
    }
  }
  std::sort(out.begin(), out.end(), [](const Transition& x, const Transition& y) { return x.period < y.period; });
  return out;
}

std::vector<Transition> OneImpactTransitionsAndCrossings(const AnalysisBasis& b, const std::vector<double>& periods,
                                                         const std::vector<bool>& admissible, int contact) {
  std::vector<Transition> out = OneImpactTransitions(b, periods, admissible, contact);
  for (const Transition& t : OneImpactMultiplierCrossings(b, periods, admissible, contact)) out.push_back(t);
  std::stable_sort(out.begin(), out.end(), [](const Transition& x, const Transition& y) { return x.period < y.period; });
  return out;
}

}  // namespace nsmodal
