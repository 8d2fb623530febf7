#include "chart.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <map>
#include <tuple>

#include "nsmodal/figure_subjects.h"
#include "nsmodal/gnuplot.h"
#include "nsmodal/trajectory.h"

namespace nsmodal::report {

std::string VerticalLines(const std::string& name, const std::vector<double>& xs, double lo, double hi) {
  std::ostringstream os;
  os << "$" << name << " << EOD\n";
  for (double x : xs) os << x << "," << lo << "\n" << x << "," << hi << "\n\n";
  os << "EOD\n";
  return os.str();
}


std::string Num(double x, int digits) {
  std::ostringstream os;
  os << std::setprecision(digits) << x;
  return os.str();
}

std::string DofLabel(const char* symbol, int dof, const char* unit) {
  return std::string(symbol) + "_{" + std::to_string(dof + 1) + "} (" + unit + ")";
}
std::string Xc(const Context& c) { return "x_{" + std::to_string(c.contact + 1) + "}"; }
std::string XcLabel(const Context& c) { return "contact displacement " + DofLabel("x", c.contact, "m"); }

void Draw(Context& c, const std::string& name, const std::string& body, const std::string& note, double aspect) {
  // Offsets keep a curve that touches d off the frame of an autoscaled axis.
  const std::string setup = "set datafile separator ','\nset offsets graph 0, graph 0, graph 0.05, graph 0.05\n";
  const report::ChartStatus s = report::DrawChart(c.dir, name, setup + body, aspect);
  (s.drawn ? c.drawn : c.failed) += 1;
  c.log << "  " << name << (note.empty() ? "" : ": " + note) << (s.drawn ? "" : ": not drawn: " + s.message) << "\n";
}

// The set-up of a multi-panel chart's one key (Plot::Legend, the plot that
// follows): an invisible frame, no object (a panel's inset ground, drawn
// again behind the key's plot, covered the inset), the key centred at the
// foot of the canvas in up to three columns, in a band `height` high
// (screen fraction) that the panels leave free.
std::string LegendPanel(double height) {
  std::ostringstream os;
  os << "unset title\nunset border\nunset tics\nunset grid\nunset arrow\nunset label\nunset object\nunset logscale\nset xlabel ''\nset ylabel ''\n"
     << "set lmargin at screen 0.01\nset rmargin at screen 0.99\nset tmargin at screen " << KeyFoot(0.0, height)
     << "\nset bmargin at screen " << KeyFoot(-0.01, height) << "\nset xrange [0:1]\nset yrange [0:1]\n"
     << "set key at screen 0.5, screen 0.005 center bottom horizontal maxcols 3\n";
  return os.str();
}

std::string KeyFoot(double labels, double band) {
  std::ostringstream os;
  os << "(" << labels << " + " << band << " * ns_key_band)";
  return os.str();
}

// A layer circling the point (t, x) as `role` (a one-point datablock).
void Mark(Plot& plot, double t, double x, const char* role, const std::string& title) {
  std::ostringstream spec;
  spec << "'+' using (" << t << "):(" << x << ") every ::0::0";
  if (title.empty()) {
    plot.Unkeyed(spec.str(), With(role));
  } else {
    plot.Add(spec.str(), With(role), title);
  }
}

// Layers marking the points (t, d) where orbits strike the obstacle.
std::function<void(Plot&)> ImpactMarks(const Context& c, const std::vector<double>& times) {
  const double d = c.b.gap;
  const std::string title = "impact: " + Xc(c) + " = d";
  return [times, d, title](Plot& plot) {
    for (std::size_t k = 0; k < times.size(); ++k) Mark(plot, times[k], d, "orbit_impact", k ? "" : title);
  };
}

bool IsStable(const std::optional<Stability>& s) { return s && s->stable; }


void WriteTrajectoryHeader(std::ostream& os, const Context& c) {
  os << "curve,T,t";
  for (int i = 1; i <= c.b.n; ++i) os << ",x" << i;
  for (int i = 1; i <= c.b.n; ++i) os << ",v" << i;
  os << "\n";
}
// `flight_rows` > 0: a row of NaN after every flight of that many rows but
// the last (the two rows of an impact are then not joined: a surface drawn
// from such scans does not bridge the jump of v_c inside the obstacle plane).
void WriteTrajectory(std::ostream& os, const std::string& label, double period, const Eigen::MatrixXd& tr,
                     long flight_rows) {
  for (long r = 0; r < tr.rows(); ++r) {
    os << label << "," << period;
    for (long k = 0; k < tr.cols(); ++k) os << "," << tr(r, k);
    os << "\n";
    if (flight_rows > 0 && (r + 1) % flight_rows == 0 && r + 1 < tr.rows()) {
      os << label << "," << period;
      for (long k = 0; k < tr.cols(); ++k) os << ",NaN";
      os << "\n";
    }
  }
  os << "\n";
}

int TCol() { return 3; }
int XCol(const Context&, int dof) { return 4 + dof; }


// Energy range of a frequency-energy plot: from 0.8 of the lowest potential
// energy (a margin of a tenth of a decade below the lowest family) up to 30
// times the median admissible one (at most four decades): the families fill
// the frame; towards a singular transition, where the energy diverges, they
// leave it at the top.
std::pair<double, double> EnergyRange(const Context& c) {
  double lo = INFINITY;
  std::vector<double> admissible;
  for (const Sweep* sweep : {&c.atlas.one, &c.atlas.two}) {
    for (const auto& list : sweep->at) {
      for (const OrbitRecord& r : list) {
        if (r.orbit.potential) lo = std::min(lo, r.orbit.energy);
        if (r.orbit.admissible) admissible.push_back(r.orbit.energy);
      }
    }
  }
  double hi = 1.0;
  if (!admissible.empty()) hi = EnergyTop(admissible);
  if (!std::isfinite(lo)) lo = 1e-3 * hi;
  return {0.8 * lo, std::min(hi, 1e4 * lo)};
}

namespace {
// LogTics' labelled mantissas on an axis `decades` long.
// (Up to 2 decades 1, 2, 3, 5 (with 1 and 3 alone, Fig. 7's colour bar had no
// label in its darkest third); with 1, 2, 5, a range from 0.25 had no
// label in its lowest third.)
std::vector<double> LogMantissas(double decades) {
  return decades <= 2.0 ? std::vector<double>{1, 2, 3, 5} : decades <= 3.5 ? std::vector<double>{1, 3} : std::vector<double>{1};
}
}  // namespace

double LogLabelledTop(double lo, double hi) {
  // (Rounding up lengthens the axis, which may thin its labels, 1, 2, 3, 5
  // to 1, 3 to 1: then `hi` rounded up among the fewer.)
  std::vector<double> mantissas = LogMantissas(std::log10(hi / lo));
  const double decade = std::pow(10.0, std::floor(std::log10(hi)));
  double top = 10.0 * decade;
  for (int pass = 0; pass < 3; ++pass) {
    top = 10.0 * decade;
    for (const double m : mantissas) {
      if (m * decade >= hi * (1 - 1e-9)) {
        top = m * decade;
        break;
      }
    }
    std::vector<double> at_top = LogMantissas(std::log10(top / lo));
    if (at_top == mantissas) break;
    mantissas = std::move(at_top);
  }
  return top;
}

std::string LogTics(const char* axis, double lo, double hi, bool ends, Beyond beyond) {
  std::ostringstream os;
  os << "set " << axis << "tics (";
  const double decades = std::log10(hi / lo);
  // (A tick within 7 % of the axis of a named end left out: "20" under
  // "23.6" on Fig. 7's bar in the column PDF.)
  auto clear = [&](double v) { return !ends || std::min(std::log10(v / lo), std::log10(hi / v)) > 0.07 * decades; };
  const std::vector<double> mantissas = LogMantissas(decades);
  bool first = true;
  for (double p = std::floor(std::log10(lo)); p <= std::ceil(std::log10(hi)); ++p) {
    for (double m : mantissas) {
      const double v = m * std::pow(10.0, p);
      if (v < lo * (1 - 1e-9) || v > hi * (1 + 1e-9) || !clear(v)) continue;
      os << (first ? "" : ", ") << "'" << v << "' " << v;
      first = false;
    }
  }
  if (ends) {
    os << (first ? "" : ", ") << "'" << (beyond.lo ? "{/Symbol \\243} " : "") << Num(lo, 3) << "' " << lo << ", '"
       << (beyond.hi ? "{/Symbol \\263} " : "") << Num(hi, 3) << "' " << hi;
    first = false;
  }
  os << ")\nset m" << axis << "tics 10\n";
  return first ? std::string("set format ") + axis + " '10^{%T}'\n" : os.str();
}

std::string InnerTics(const char* axis, double lo, double hi, int ticks) {
  const double step = NiceStep(lo, hi, ticks);
  const double first = std::ceil((lo + 0.4 * step) / step) * step, last = std::floor((hi - 0.4 * step) / step) * step;
  std::ostringstream os;
  if (first <= last) {
    os << "set " << axis << "tics " << first << ", " << step << ", " << last << "\n";
  } else {
    os << "set " << axis << "tics " << step << "\n";
  }
  return os.str();
}

namespace {

// A bridge too short to see at a frequency-energy chart's scale (under 4 %
// of its energy axis's height): zoomed on in an inset (BridgeInsets), the
// window T within 2.5 % of the period axis on each side (its box wider than
// the grazing circle in every format).
bool ShortBridge(const Context& c, const Bridge& b) {
  const auto [lo, hi] = EnergyRange(c);
  return b.energy_max > b.energy_min && std::log(b.energy_max / b.energy_min) <= 0.04 * std::log(hi / lo);
}
constexpr double kBridgeWindow = 0.025, kBridgeBox = 0.07;

}  // namespace

void BridgeLabels(const Context& c, std::ostream& body) {
  for (std::size_t k = 0; k < c.bridges.size(); ++k) {
    const Bridge& b = c.bridges[k];
    if (ShortBridge(c, b)) {
      // Left of its window's box, whose leader rises from the box's top
      // through a label above it.
      body << "set label 'B" << k + 1 << "' at " << b.period - kBridgeWindow * PeriodTop(c, false) << ", "
           << std::sqrt(b.energy_min * b.energy_max) << " right offset -0.4, 0 front\n";
    } else {
      body << "set label 'B" << k + 1 << "' at " << b.period << ", " << b.energy_max << " offset -0.6, 1.1 front\n";
    }
  }
}

std::string FamilyBarTics(double lo, double hi) {
  std::ostringstream os;
  if (!(hi > lo)) {  // (one value: a step of 0 would never end)
    os << "set cbtics ('" << Num(lo, 3) << "' 0)\n";
    return os.str();
  }
  // About four ticks; more (up to seven) where a finer round step lands on
  // both ends (Fig. 14's 0 to 0.5 read 0, 0.2, 0.4, 0.5, unevenly spaced).
  auto on_step = [](double x, double s) { return std::abs(x / s - std::round(x / s)) < 1e-9; };
  double step = NiceStep(lo, hi, 4);
  if (!(on_step(lo, step) && on_step(hi, step))) {
    for (const int count : {6, 8}) {
      const double finer = NiceStep(lo, hi, count);
      if (on_step(lo, finer) && on_step(hi, finer) && (hi - lo) / finer < 7.5) {
        step = finer;
        break;
      }
    }
  }
  // The family's ends always named (at 40 % of a step from a round value,
  // Fig. 10's dark end, 5.145 beside 5.2, was not named and a reader asked
  // for it), and a round value within half a step of a named end dropped
  // (at 30 %, "5.14" and "5.2" crowded each other).
  const double tol = 1e-9 * std::max(std::abs(lo), std::abs(hi));
  const bool lo_round = on_step(lo, step), hi_round = on_step(hi, step);
  os << "set cbtics (";
  bool first = true;
  auto tick = [&](const std::string& label, double at) {
    os << (first ? "" : ", ") << "'" << label << "' " << at + 0.0;
    first = false;
  };
  if (!lo_round) tick(Num(lo, 3), 0.0);
  for (double v = std::ceil(lo / step - 1e-9) * step; v <= hi + tol; v += step) {
    if ((!lo_round && v - lo < 0.5 * step) || (!hi_round && hi - v < 0.5 * step)) continue;
    // (+ 0.0: a tick at zero reads 0, not -0.)
    std::ostringstream label;
    label << v + 0.0;
    tick(label.str(), (v - lo) / (hi - lo));
  }
  if (!hi_round) tick(Num(hi, 3), 1.0);
  os << ")\n";
  return os.str();
}

namespace {

// A fold in T, where two roots meet and vanish between two steps: the two
// branches that end (or begin) at the same step, adjacent in t2 / T (no root
// of that step between them, nor t2 = T/2), within 0.2 of each other and
// clear of t2 = 0 and T (where a branch leaves through the frame's edge, not
// a fold), are one curve turning back: joined end to end (the one entered at
// its end reversed), the nearest pairs first. `roots`: every root, by step
// and t2.
std::vector<std::vector<FepTable::Root>> JoinFolds(std::vector<std::vector<FepTable::Root>> branches,
                                                   const std::vector<FepTable::Root>& roots) {
  using Root = FepTable::Root;
  auto u = [](const Root& r) { return r.t2 / r.period; };
  if (roots.empty()) return branches;
  const int first = roots.front().step, last = roots.back().step;
  std::map<int, std::vector<double>> at_step;  // each step's roots' t2 / T, ascending (roots are sorted so)
  for (const Root& r : roots) at_step[r.step].push_back(u(r));
  // The endpoints at each step: (u, branch, side) with side 0 a start, 1 an end.
  struct End {
    double u;
    std::size_t branch;
    int side;
  };
  std::map<std::pair<int, int>, std::vector<End>> ends;  // (step, side) -> its endpoints
  for (std::size_t b = 0; b < branches.size(); ++b) {
    const Root& head = branches[b].front();
    const Root& tail = branches[b].back();
    if (head.step > first) ends[{head.step, 0}].push_back({u(head), b, 0});
    if (tail.step < last) ends[{tail.step, 1}].push_back({u(tail), b, 1});
  }
  std::map<std::pair<std::size_t, int>, std::pair<std::size_t, int>> partner;
  for (auto& [key, list] : ends) {
    const std::vector<double>& all = at_step[key.first];
    struct Pair {
      double d;
      std::size_t a, b;
    };
    std::vector<Pair> pairs;
    for (std::size_t i = 0; i < list.size(); ++i) {
      for (std::size_t j = i + 1; j < list.size(); ++j) {
        const double lo = std::min(list[i].u, list[j].u), hi = std::max(list[i].u, list[j].u);
        if (list[i].branch == list[j].branch || hi - lo > 0.2 || lo < 0.01 || hi > 0.99) continue;
        // (The trivial root t2 = T/2 lies between them too: two branches
        // leaving it at a pitchfork are not a fold.)
        const bool between = (lo < 0.5 && hi > 0.5) ||
                             std::any_of(all.begin(), all.end(), [&](double x) { return x > lo && x < hi; });
        if (!between) pairs.push_back({hi - lo, i, j});
      }
    }
    std::sort(pairs.begin(), pairs.end(), [](const Pair& x, const Pair& y) { return x.d < y.d; });
    for (const Pair& p : pairs) {
      const End &a = list[p.a], &b = list[p.b];
      if (partner.count({a.branch, a.side}) || partner.count({b.branch, b.side})) continue;
      partner[{a.branch, a.side}] = {b.branch, b.side};
      partner[{b.branch, b.side}] = {a.branch, a.side};
    }
  }
  if (partner.empty()) return branches;
  // Each chain walked from an unpaired end (a loop of folds from anywhere).
  std::vector<bool> used(branches.size(), false);
  std::vector<std::vector<Root>> joined;
  auto walk = [&](std::size_t b, int enter) {
    std::vector<Root> chain;
    while (!used[b]) {
      used[b] = true;
      if (enter == 0) {
        chain.insert(chain.end(), branches[b].begin(), branches[b].end());
      } else {
        chain.insert(chain.end(), branches[b].rbegin(), branches[b].rend());
      }
      const auto it = partner.find({b, 1 - enter});
      if (it == partner.end()) break;
      std::tie(b, enter) = it->second;
    }
    joined.push_back(std::move(chain));
  };
  for (std::size_t b = 0; b < branches.size(); ++b) {
    if (used[b]) continue;
    if (!partner.count({b, 0})) {
      walk(b, 0);
    } else if (!partner.count({b, 1})) {
      walk(b, 1);
    }
  }
  for (std::size_t b = 0; b < branches.size(); ++b) {
    if (!used[b]) walk(b, 0);
  }
  return joined;
}

}  // namespace

std::vector<std::vector<FepTable::Root>> TwoImpactBranches(std::vector<FepTable::Root> roots) {
  using Root = FepTable::Root;
  std::sort(roots.begin(), roots.end(),
            [](const Root& a, const Root& b) { return a.step != b.step ? a.step < b.step : a.t2 < b.t2; });
  // A root in the plane (t2 / T, log E), where the branches are smooth
  // curves of the step.
  struct Point {
    double u, v;
  };
  auto at = [](const Root& r) { return Point{r.t2 / r.period, std::log(r.energy)}; };
  std::vector<std::vector<Root>> done, open;
  for (std::size_t i = 0; i < roots.size();) {
    std::size_t j = i;
    while (j < roots.size() && roots[j].step == roots[i].step) ++j;
    // Every (open branch, root) pair near enough, nearest first: a branch of
    // two points or more is extrapolated (its next point predicted from its
    // last two, so that a steep branch is followed), a branch of one point
    // is compared with that point, with a looser bound.
    struct Link {
      double d;
      std::size_t branch, root;
    };
    std::vector<Link> links;
    for (std::size_t o = 0; o < open.size(); ++o) {
      const std::vector<Root>& branch = open[o];
      const Root& last = branch.back();
      if (last.step != roots[i].step - 1 || !(last.energy > 0.0)) continue;
      const Point p = at(last);
      const bool extrapolate = branch.size() >= 2 && branch[branch.size() - 2].step == last.step - 1;
      const Point q = extrapolate ? at(branch[branch.size() - 2]) : p;
      const Point predicted{2.0 * p.u - q.u, 2.0 * p.v - q.v};
      const double bound = extrapolate ? 0.05 : 0.25;  // beyond: not the same branch
      for (std::size_t k = i; k < j; ++k) {
        if (!(roots[k].energy > 0.0)) continue;
        const Point r = at(roots[k]);
        const double d = std::abs(r.u - predicted.u) + std::abs(r.v - predicted.v);
        if (d < bound) links.push_back({d, o, k});
      }
    }
    std::sort(links.begin(), links.end(), [](const Link& a, const Link& b) { return a.d < b.d; });
    std::vector<bool> root_used(j - i, false), branch_used(open.size(), false);
    std::vector<std::vector<Root>> next;
    for (const Link& l : links) {
      if (root_used[l.root - i] || branch_used[l.branch]) continue;
      root_used[l.root - i] = branch_used[l.branch] = true;
      open[l.branch].push_back(roots[l.root]);
      next.push_back(std::move(open[l.branch]));
    }
    for (std::size_t o = 0; o < open.size(); ++o) {
      if (!branch_used[o]) done.push_back(std::move(open[o]));
    }
    for (std::size_t k = i; k < j; ++k) {
      if (!root_used[k - i]) next.push_back({roots[k]});
    }
    open = std::move(next);
    i = j;
  }
  for (std::vector<Root>& branch : open) done.push_back(std::move(branch));
  return JoinFolds(std::move(done), roots);
}

std::string FepChart(Context& c, const FepTable& table, const std::string& fep, const std::string& bridges,
                     const std::string& transitions, const std::vector<Orbit>& also, const std::vector<Zoom>& zooms) {
  report::ResultFile out(c.dir, fep);
  table.Write(out.stream());
  out.Commit();
  report::ResultFile br(c.dir, bridges);
  WriteBridges(br.stream(), c.bridges);
  br.Commit();
  std::ostringstream body;
  body << EnergyAxes(c);
  // The transition lines under the families, their marks over them.
  Plot plot;
  TransitionLines(c, transitions, false, body, plot);
  table.AddLayers(plot, fep, bridges, static_cast<long>(c.bridges.size()));
  TransitionMarks(c, transitions, false, plot);
  BridgeLabels(c, body);
  body << BridgeInsets(c, plot, also, zooms);
  return body.str();
}

Occupancy::Occupancy(double t_lo, double t_hi, double e_lo, double e_hi, bool log_e)
    : t_lo_(t_lo), t_hi_(t_hi), e_lo_(e_lo), e_hi_(e_hi), log_e_(log_e) {}

double Occupancy::X(double t) const { return (t - t_lo_) / (t_hi_ - t_lo_); }

double Occupancy::Y(double e) const {
  return log_e_ ? std::log(e / e_lo_) / std::log(e_hi_ / e_lo_) : (e - e_lo_) / (e_hi_ - e_lo_);
}

double Occupancy::T(double fx) const { return t_lo_ + fx * (t_hi_ - t_lo_); }

double Occupancy::E(double fy) const {
  return log_e_ ? e_lo_ * std::pow(e_hi_ / e_lo_, fy) : e_lo_ + fy * (e_hi_ - e_lo_);
}

void Occupancy::Mark(double fx, double fy, long weight) {
  if (fx < 0.0 || fx >= 1.0 || fy < 0.0 || fy >= 1.0 || !std::isfinite(fx) || !std::isfinite(fy)) return;
  long& cell = cells_[static_cast<int>(fx * kCells) * kCells + static_cast<int>(fy * kCells)];
  cell = std::max(cell, weight);
}

void Occupancy::MarkBox(double x0, double y0, double x1, double y1, long weight) {
  for (double x = x0; x <= x1; x += 0.5 / kCells) {
    for (double y = y0; y <= y1; y += 0.5 / kCells) Mark(x, y, weight);
  }
}

void Occupancy::MarkSegment(double x0, double y0, double x1, double y1, int steps) {
  for (int i = 0; i <= steps; ++i) Mark(x0 + (x1 - x0) * i / steps, y0 + (y1 - y0) * i / steps);
}

long Occupancy::Count(double x0, double y0, double x1, double y1) const {
  long n = 0;
  for (int i = std::max(0, static_cast<int>(x0 * kCells)); i < std::min(kCells, static_cast<int>(x1 * kCells) + 1); ++i) {
    for (int j = std::max(0, static_cast<int>(y0 * kCells)); j < std::min(kCells, static_cast<int>(y1 * kCells) + 1);
         ++j) {
      n += cells_[i * kCells + j];
    }
  }
  return n;
}

namespace {

// The frame of a frequency-energy chart (EnergyAxes): what it draws, as
// occupied cells. The admissible orbits (the 1-ipp ones alone if
// `one_only`), the singular transitions' lines, the bridges and their labels.
Occupancy FepOccupancy(const Context& c, bool one_only) {
  const auto [lo, hi] = EnergyRange(c);
  Occupancy free(0.0, PeriodTop(c, one_only), lo, hi);
  for (const Sweep* sweep : {&c.atlas.one, &c.atlas.two}) {
    if (one_only && sweep != &c.atlas.one) continue;
    for (const auto& list : sweep->at) {
      for (const OrbitRecord& r : list) {
        if (r.orbit.admissible) {
          free.Mark(free.X(r.orbit.period), free.Y(r.orbit.energy));
        } else if (one_only && r.orbit.potential) {  // (Fig. 3 draws them)
          free.Mark(free.X(r.orbit.period), free.Y(r.orbit.energy), Occupancy::kContext);
        }
      }
    }
  }
  // The lines between them, as the charts draw them: the 1-ipp branch and
  // the orbits with t2 = T/2 step to step, the other 2-ipp roots joined into
  // branches (TwoImpactBranches). (The orbits alone left the cells of a
  // steep stretch free between them: Fig. 8's B3 leader crossed the 2-ipp
  // branch at T = 35.5.)
  auto segment = [&free](double t0, double e0, double t1, double e1) {
    free.MarkSegment(free.X(t0), free.Y(e0), free.X(t1), free.Y(e1), 50);
  };
  const auto& one = c.atlas.one.at;
  for (std::size_t k = 1; k < one.size(); ++k) {
    if (!one[k - 1].empty() && !one[k].empty() && one[k - 1].front().orbit.admissible && one[k].front().orbit.admissible) {
      const Orbit &a = one[k - 1].front().orbit, &b = one[k].front().orbit;
      segment(a.period, a.energy, b.period, b.energy);
    }
  }
  if (!one_only) {
    std::vector<FepTable::Root> roots;
    const Orbit* half_before = nullptr;
    for (std::size_t k = 0; k < c.atlas.two.at.size(); ++k) {
      const Orbit* half = nullptr;
      for (const OrbitRecord& r : c.atlas.two.at[k]) {
        if (!r.orbit.admissible) continue;
        if (IsHalfPeriodRoot(r.orbit)) {
          half = &r.orbit;
        } else {
          roots.push_back({static_cast<int>(k), r.orbit.period, r.orbit.times[0], r.orbit.energy, false});
        }
      }
      if (half && half_before) segment(half_before->period, half_before->energy, half->period, half->energy);
      half_before = half;
    }
    for (const auto& branch : TwoImpactBranches(std::move(roots))) {
      for (std::size_t i = 1; i < branch.size(); ++i) {
        segment(branch[i - 1].period, branch[i - 1].energy, branch[i].period, branch[i].energy);
      }
    }
  }
  for (const Transition& t : c.transitions) {
    if (t.kind == TransitionKind::kSingular) free.MarkBox(free.X(t.period), 0.0, free.X(t.period), 1.0);
    // A mark drawn (TransitionMarks: every kind on the 1-ipp chart, the
    // grazing ones on the others), with its label to its left (T_G).
    const bool drawn = one_only ? t.kind != TransitionKind::kSingular : t.kind == TransitionKind::kGrazing;
    if (drawn && t.energy >= lo && t.energy <= hi) {
      free.MarkBox(free.X(t.period) - 0.07, free.Y(t.energy) - 0.03, free.X(t.period) + 0.02, free.Y(t.energy) + 0.03);
    }
  }
  if (!one_only) {
    // Each bridge with its label (BridgeLabels): above it, or, zoomed on,
    // left of its window's box.
    const double window = kBridgeWindow * PeriodTop(c, false);
    for (const Bridge& b : c.bridges) {
      if (ShortBridge(c, b)) {
        const double label_y = free.Y(std::sqrt(b.energy_min * b.energy_max));
        free.MarkBox(free.X(b.period) - 0.01, free.Y(b.energy_min), free.X(b.period) + 0.01, free.Y(b.energy_max));
        free.MarkBox(free.X(b.period - window) - 0.05, label_y - 0.03, free.X(b.period - window), label_y + 0.03);
      } else {
        free.MarkBox(free.X(b.period) - 0.03, free.Y(b.energy_min), free.X(b.period) + 0.01, free.Y(b.energy_max) + 0.08);
      }
    }
  }
  return free;
}

}  // namespace

std::string ZoomInsets(const Context& c, const Plot& plot, bool one_only, const std::vector<Zoom>& zooms) {
  return ZoomInsets(FepOccupancy(c, one_only), plot, zooms, false);
}

std::string ZoomInsets(Occupancy free, const Plot& plot, const std::vector<Zoom>& zooms, bool in_multiplot) {
  // An inset (by default 27 % of the frame's width, 30 % of its height), two
  // tick labels on each axis, outside its own frame and on its white ground
  // (inside the frame they lay on its curves; beyond the ground, on the
  // chart's). kLeft, kBelow: about where its frame starts (the leader's end).
  constexpr double kLeft = 0.06, kBelow = 0.075, kEdge = 0.012;
  constexpr double kMinBox[2] = {0.025, 0.035};  // (a window's box on the chart, as fractions of the frame)
  std::ostringstream boxes, insets;
  int shown = 0;
  for (std::size_t i = 0; i < zooms.size(); ++i) {
    const Zoom& z = zooms[i];
    // Where this inset may go: the frame as drawn so far, and the windows
    // still to zoom on with their corridors to the top (on Fig. 3's column
    // PDF, the first inset sat right above the second's window, whose
    // leader then ran through its labels).
    Occupancy here = free;
    for (std::size_t j = i + 1; j < zooms.size(); ++j) {
      const double mid = free.X(0.5 * (zooms[j].t_lo + zooms[j].t_hi));
      here.MarkBox(free.X(zooms[j].t_lo), free.Y(zooms[j].e_lo), free.X(zooms[j].t_hi), free.Y(zooms[j].e_hi));
      here.MarkBox(mid - 0.02, free.Y(zooms[j].e_hi), mid + 0.02, 1.0, Occupancy::kCorridor);
    }
    // The free place nearest the zoomed window, highest first: fewest cells
    // covered, then nearest, then with a leader crossing the least of the
    // subject; clear of the frame's edges (the inset's ground cut them).
    // At its size, or at 80 % or 65 % of it: the largest whose best place
    // hides nothing of the subject and has a leader crossing none of it;
    // else the largest whose best place hides nothing (fep_all_families'
    // third inset found no place at its size; response_energy's, at 0.34
    // of the frame, found one only in the far corner, behind a leader
    // across the chart). (`at`: the window's middle in the frame.)
    double w = z.width, h = z.height;
    const double at = free.X(0.5 * (z.t_lo + z.t_hi));
    // The window's box on the chart, at least kMinBox of the frame about its
    // middle: a smaller one was not seen (Fig. 16's, 0.8 % by 0.1 %, and
    // Fig. 3's at T = 20.3 in the column PDF); the inset's ticks give the
    // window itself.
    auto at_least = [](double& lo, double& hi, double least) {
      if (hi - lo >= least) return;
      const double mid = 0.5 * (lo + hi);
      lo = mid - 0.5 * least;
      hi = mid + 0.5 * least;
    };
    double fx0 = free.X(z.t_lo), fx1 = free.X(z.t_hi), fy0 = free.Y(z.e_lo), fy1 = free.Y(z.e_hi);
    at_least(fx0, fx1, kMinBox[0]);
    at_least(fy0, fy1, kMinBox[1]);
    const double box_top = fy1, box_bottom = fy0;
    // The inset's period ticks, as fractions of its frame's width.
    std::vector<double> ticks = {0.5};
    if (!z.one_period_tick) {
      const auto [first, last] = TwoTickValues(z.t_lo, z.t_hi);
      ticks = {(first - z.t_lo) / (z.t_hi - z.t_lo), (last - z.t_lo) / (z.t_hi - z.t_lo)};
    }
    // Where the leader ends on the frame placed at (x, y), as a fraction of
    // its width: into its top, above the window's middle; into its foot
    // (above the box), where no period label can be, whatever this format's
    // label widths: between the two labels, or, with one, at the corner
    // nearer the window. (On the column PDF, Fig. 3's leader ran through the
    // upper inset's "20", and Fig. 16's, at the window's place, through the
    // "6" of its one label "28.86".)
    auto end_fraction = [&](double x, double y) {
      const double x0 = x + kLeft, x1 = x + w - kEdge;
      if (y + kBelow < box_top) return std::clamp((at - x0) / (x1 - x0), 0.0, 1.0);
      if (ticks.size() == 2) return 0.5 * (ticks[0] + ticks[1]);
      return at < 0.5 * (x0 + x1) ? 0.0 : 1.0;
    };
    // The leader from the window's box to the inset's frame placed at (x, y):
    // into its foot (above the box) or its top.
    auto leader = [&](double x, double y) {
      const double x0 = x + kLeft, x1 = x + w - kEdge, y0 = y + kBelow, y1 = y + h - kEdge;
      const bool above = y0 >= box_top;
      return std::array<double, 4>{at, above ? box_top : box_bottom, x0 + end_fraction(x, y) * (x1 - x0), above ? y0 : y1};
    };
    double best = INFINITY, bx = 0.0, by = 0.0, b_scale = 1.0;
    bool clear = false;  // (the chosen place's leader crosses nothing of the subject)
    for (const double scale : {1.0, 0.8, 0.65}) {
      w = scale * z.width;
      h = scale * z.height;
      double in_scale = INFINITY, sx = 0.0, sy = 0.0;
      int s_crossed = 0;
      for (double y = 1.0 - h - 0.01; y >= 0.01; y -= 0.02) {
        for (double x = 0.01; x <= 1.0 - w - 0.01 + 1e-9; x += 0.01) {
          const std::array<double, 4> l = leader(x, y);
          int crossed = 0;
          for (int i = 1; i < 40; ++i) {
            const double fx = l[0] + (l[2] - l[0]) * i / 40.0, fy = l[1] + (l[3] - l[1]) * i / 40.0;
            crossed += here.Count(fx, fy, fx, fy) >= Occupancy::kSubject;
          }
          const double cost = static_cast<double>(here.Count(x, y, x + w, y + h)) + std::abs(x + 0.5 * w - at) +
                              0.5 * (1.0 - h - y) + 4.0 * crossed / 40.0;
          if (cost < in_scale) {
            in_scale = cost;
            sx = x;
            sy = y;
            s_crossed = crossed;
          }
        }
      }
      if (in_scale >= Occupancy::kSubject) continue;
      if (best >= Occupancy::kSubject || (!clear && s_crossed == 0)) {
        best = in_scale;
        bx = sx;
        by = sy;
        b_scale = scale;
        clear = s_crossed == 0;
      }
      if (clear) break;
    }
    if (best >= Occupancy::kSubject) continue;  // (no place that hides nothing of the subject: not zoomed)
    w = b_scale * z.width;
    h = b_scale * z.height;
    // (With a margin: the next inset's ground would cut this one's labels.)
    free.MarkBox(bx - 0.03, by - 0.03, bx + w + 0.03, by + h + 0.03);
    // (And its leader: the next inset neither covers it nor crosses it.)
    {
      const std::array<double, 4> l = leader(bx, by);
      free.MarkSegment(l[0], l[1], l[2], l[3], 40);
    }
    free.MarkBox(fx0, fy0, fx1, fy1);
    ++shown;
    boxes << "set object " << 10 + shown << " rect from " << free.T(fx0) << ", " << free.E(fy0) << " to " << free.T(fx1)
          << ", " << free.E(fy1)
          // (gnuplot draws no border given as "border lw ...": its colour first.)
          << " front fillstyle empty border lc rgb '" << style::RoleColour("leader") << "' "
          << style::Look("leader", "lines") << "\n";
    // In the inset: the frame placed on the main frame (gnuplot's terminal
    // coordinates of the plot before, GPVAL_TERM_*, as fractions of the
    // canvas), a white ground under it and its tick labels; E linear.
    auto sx = [](double f) { return "(ns_x0 + " + std::to_string(f) + " * (ns_x1 - ns_x0))"; };
    auto sy = [](double f) { return "(ns_y0 + " + std::to_string(f) + " * (ns_y1 - ns_y0))"; };
    insets << "unset object\nunset label\nunset arrow\nunset key\nunset title\nunset logscale y\nunset xlabel\nunset ylabel\n"
           << "set object 1 rect from screen " << sx(bx) << ", screen " << sy(by) << " to screen " << sx(bx + w)
           << ", screen " << sy(by + h) << " behind fillcolor rgb '" << style::Colour("white")
           << "' fillstyle solid 1.0 noborder\n";
    // Its frame inside the ground, clear of its tick labels at their width
    // in this format's characters (ns_hc, ns_vc: a character's width and
    // height as fractions of the canvas): the energy's widest label and a
    // character to the left, a line and a half below.
    const auto [e_first, e_last] = TwoTickValues(z.e_lo, z.e_hi);
    std::ostringstream first_label, last_label;
    first_label << e_first;
    last_label << e_last;
    const std::size_t chars = std::max(first_label.str().size(), last_label.str().size());
    // (Streams, not "(" + ... chains: GCC 12's -Wrestrict false positive.)
    std::ostringstream left_os;
    left_os << "(" << sx(bx + kEdge) << " + " << chars + 1 << " * ns_hc)";
    const std::string frame_left = left_os.str(), frame_right = sx(bx + w - kEdge);
    {
      // A leader from the box's side facing the inset to the inset's frame,
      // drawn with the inset (over its ground, which covered a leader drawn
      // with the chart); its end on the frame as this format places it
      // (kLeft is about the PNG's; the column PDF's labels are wider).
      // (Thin and solid: dotted, it read as a non-admissible branch; light
      // grey, it was not seen; grey, as Fig. 3's potential orbits.)
      const std::array<double, 4> l = leader(bx, by);
      std::ostringstream end_os;
      end_os << "(" << frame_left << " + " << end_fraction(bx, by) << " * (" << frame_right << " - " << frame_left << "))";
      std::string look = " ";  // (not " " + ...: GCC 12's -Wrestrict false positive on it)
      look += style::Look("leader") + " front\n";
      const std::string end = end_os.str();
      if (l[3] > l[1]) {
        // Into the foot: to the ground's edge below the gap, then straight
        // up through the gap to the frame. (Slanted through the labels'
        // band, it cut "28.86" and "0.52" in the column PDF, whose labels
        // are wider than the PNG's.)
        insets << "set arrow from screen " << sx(l[0]) << ", screen " << sy(l[1]) << " to screen " << end << ", screen "
               << sy(by) << look << "set arrow from screen " << end << ", screen " << sy(by) << " to screen " << end
               << ", screen (" << sy(by + kEdge) << " + 1.5 * ns_vc)" << look;
      } else {
        insets << "set arrow from screen " << sx(l[0]) << ", screen " << sy(l[1]) << " to screen " << end << ", screen "
               << sy(l[3]) << look;
      }
    }
    insets << "set lmargin at screen " << frame_left << "\nset rmargin at screen "
           << frame_right << "\nset bmargin at screen (" << sy(by + kEdge) << " + 1.5 * ns_vc)\nset tmargin at screen "
           << sy(by + h - kEdge) << "\n"
           << "set xrange [" << z.t_lo << ":" << z.t_hi << "]\nset yrange [" << z.e_lo << ":" << z.e_hi << "]\n"
           << "set xtics " << (z.one_period_tick ? OneTick(0.5 * (z.t_lo + z.t_hi)) : TwoTicks(z.t_lo, z.t_hi))
           << "\nset ytics " << TwoTicks(z.e_lo, z.e_hi)
           << "\nset tics scale 0.5\nset mytics default\nset format y '%g'\n"
           << (z.label.empty() ? ""
               : "set label '" + z.label + (z.label_centred ? "' at graph 0.5, graph 0.86 centre front\n"
                                                             : "' at graph 0.06, graph 0.86 front\n"))
           << plot.Untitled();
  }
  if (shown == 0) return plot.str();
  return boxes.str() + (in_multiplot ? "" : "set multiplot\n") + plot.str() +
         "ns_x0 = GPVAL_TERM_XMIN * GPVAL_TERM_SCALE * 1.0 / GPVAL_TERM_XSIZE\n"
         "ns_x1 = GPVAL_TERM_XMAX * GPVAL_TERM_SCALE * 1.0 / GPVAL_TERM_XSIZE\n"
         "ns_y0 = GPVAL_TERM_YMIN * GPVAL_TERM_SCALE * 1.0 / GPVAL_TERM_YSIZE\n"
         "ns_y1 = GPVAL_TERM_YMAX * GPVAL_TERM_SCALE * 1.0 / GPVAL_TERM_YSIZE\n"
         "ns_hc = GPVAL_TERM_HCHAR * 1.0 / GPVAL_TERM_XSIZE\nns_vc = GPVAL_TERM_VCHAR * 1.0 / GPVAL_TERM_YSIZE\n" +
         insets.str() + (in_multiplot ? "" : "unset multiplot\n");
}

std::pair<double, double> StretchWindow(double first, double last, double axis, double min_half) {
  const double mid = 0.5 * (first + last), half = std::max(1.5 * (last - first), min_half * axis);
  return {mid - half, mid + half};
}

std::pair<double, double> EnergySpan(const std::vector<Orbit>& orbits, double t_lo, double t_hi) {
  double e_lo = INFINITY, e_hi = 0.0;
  for (const Orbit& o : orbits) {
    if (o.period >= t_lo && o.period <= t_hi) {
      e_lo = std::min(e_lo, o.energy);
      e_hi = std::max(e_hi, o.energy);
    }
  }
  return {e_lo, e_hi};
}

std::string BridgeInsets(const Context& c, const Plot& plot, const std::vector<Orbit>& also,
                         const std::vector<Zoom>& more) {
  const double t_top = PeriodTop(c, false);
  const auto [axis_lo, axis_hi] = EnergyRange(c);
  std::vector<Zoom> zooms;
  std::vector<double> at;  // each zoom's bridge's period
  for (std::size_t k = 0; k < c.bridges.size(); ++k) {
    const Bridge& b = c.bridges[k];
    if (!ShortBridge(c, b)) continue;  // (seen at the chart's scale)
    // The zoom: the bridge over 2/3 of the inset's height, its window's box
    // on the chart at least kBridgeBox of the energy axis high (log): a
    // smaller box sat inside the grazing circle and the bridge's caps, and
    // box, marks and label read as one spot in the column PDF.
    const double pad = 0.25 * (b.energy_max - b.energy_min), dt = kBridgeWindow * t_top;
    double e_lo = b.energy_min - pad, e_hi = b.energy_max + pad;
    const double least = std::pow(axis_hi / axis_lo, kBridgeBox);
    if (!(e_lo > 0.0) || e_hi / e_lo < least) {
      const double mid = std::sqrt(b.energy_min * b.energy_max);
      e_lo = mid / std::sqrt(least);
      e_hi = mid * std::sqrt(least);
    }
    std::string label = "B";  // (not "B" + ...: GCC 12's -Wrestrict false positive on it)
    label += std::to_string(k + 1);
    zooms.push_back({b.period - dt, b.period + dt, e_lo, e_hi, label});
    at.push_back(b.period);
  }
  // A window within a bridge's is shown in the bridge's inset, narrowed to
  // both (15 % of their span beyond): two insets side by side found no free
  // place for the second (on paper.toml, the 3-ipp family's stable stretch
  // at T = 28.85 beside B3 at 29.31).
  const std::size_t bridge_zooms = zooms.size();
  for (const Zoom& m : more) {
    std::size_t k = 0;
    while (k < bridge_zooms && !(m.t_lo >= zooms[k].t_lo && m.t_hi <= zooms[k].t_hi)) ++k;
    if (k == bridge_zooms) {
      zooms.push_back(m);
      continue;
    }
    Zoom& z = zooms[k];
    const double first = std::min(m.t_lo, at[k]), last = std::max(m.t_hi, at[k]), pad = 0.15 * (last - first);
    z.t_lo = first - pad;
    z.t_hi = last + pad;
    z.e_lo = std::min(z.e_lo, m.e_lo);
    z.e_hi = std::max(z.e_hi, m.e_hi);
  }
  Occupancy free = FepOccupancy(c, false);
  for (const Orbit& o : also) free.Mark(free.X(o.period), free.Y(o.energy));
  return ZoomInsets(free, plot, zooms, false);
}

std::string StableStretchInsets(const Context& c, const Plot& plot) {
  const double t_top = PeriodTop(c, true);
  // The admissible 1-ipp branch's stable stretches, each as its first and
  // last period.
  StableStretches found;
  for (const auto& list : c.atlas.one.at) {
    const OrbitRecord& r = list.front();
    found.Add(r.orbit.period, r.orbit.admissible && IsStable(r.stability));
  }
  std::vector<std::pair<double, double>>& stretches = found.stretches();
  // (Seen at the chart's scale: a stretch over 1 % of the period axis.)
  std::erase_if(stretches, [&](const auto& s) { return s.second - s.first > 0.01 * t_top; });
  // Two marks of the chart (TransitionMarks) on each other, under 1 % of the
  // period axis and 4 % of the energy axis apart (on paper.toml the +1
  // triangle at 20.18 sat on the modal pentagon at 20.37, the unstable
  // stretch between them hidden): zoomed on too, unless a stretch's zoom
  // holds them.
  const auto [lo, hi] = EnergyRange(c);
  std::vector<const Transition*> marks;
  for (const Transition& t : c.transitions) {
    if (t.kind != TransitionKind::kSingular && t.energy >= lo && t.energy <= hi) marks.push_back(&t);
  }
  std::sort(marks.begin(), marks.end(), [](const Transition* a, const Transition* b) { return a->period < b->period; });
  for (std::size_t k = 0; k + 1 < marks.size(); ++k) {
    const Transition &a = *marks[k], &b = *marks[k + 1];
    if (b.period - a.period > 0.01 * t_top || std::abs(std::log(b.energy / a.energy)) > 0.04 * std::log(hi / lo)) continue;
    const bool held = std::any_of(stretches.begin(), stretches.end(), [&](const auto& s) {
      const auto [w_lo, w_hi] = StretchWindow(s.first, s.second, t_top);
      return a.period >= w_lo && b.period <= w_hi;
    });
    if (!held) stretches.push_back({a.period, b.period});
  }
  std::vector<Zoom> zooms;
  for (const auto& [first, last] : stretches) {
    // The zoom: the stretch in its middle third (at least 1 % of the axis
    // wide), the admissible branch's energies there.
    const auto [w_lo, w_hi] = StretchWindow(first, last, t_top);
    double e_lo = INFINITY, e_hi = 0.0;
    for (const auto& list : c.atlas.one.at) {
      const Orbit& o = list.front().orbit;
      if (o.admissible && o.period >= w_lo && o.period <= w_hi) {
        e_lo = std::min(e_lo, o.energy);
        e_hi = std::max(e_hi, o.energy);
      }
    }
    for (const Transition* t : marks) {  // (a modal end lies above the sweep's last orbit)
      if (t->period >= w_lo && t->period <= w_hi) {
        e_lo = std::min(e_lo, t->energy);
        e_hi = std::max(e_hi, t->energy);
      }
    }
    if (!(e_hi > e_lo)) continue;
    // (Its foot above 0: the box is drawn on the chart's log axis.)
    const double pad = 0.15 * (e_hi - e_lo);
    zooms.push_back({w_lo, w_hi, std::max(e_lo - pad, 0.5 * e_lo), e_hi + pad, ""});
  }
  return ZoomInsets(c, plot, true, zooms);
}

void FepTable::Write(std::ostream& out, bool short_at_middle) const {
  // One blank line between the families and the branches (two would start
  // a new dataset).
  out << "family,T,t2,energy,stable,branch,mark\n";
  bool first = true;
  for (const Family* f : {&one_, &half_}) {
    if (f->last < 0) continue;
    out << (first ? "" : "\n") << f->rows.str();
    first = false;
  }
  // The 2-ipp branches and the 3-ipp family marked at equal steps of one
  // frame; no 3-ipp mark within three orbits of a stable one (its dot: on
  // paper.toml an unstable square at T = 28.87 covered the stable dots at
  // 28.85 and 28.86).
  std::vector<std::vector<Root>> branches = TwoImpactBranches(roots_);
  branches.push_back(three_rows_);
  std::vector<std::vector<bool>> marks = EqualStepMarks(branches, short_at_middle);
  branches.pop_back();
  std::vector<bool> three_marks = std::move(marks.back());
  marks.pop_back();
  for (std::size_t k = 0; k < three_rows_.size(); ++k) {
    if (!three_rows_[k].stable) continue;
    for (std::size_t j = k >= 3 ? k - 3 : 0; j < std::min(k + 4, three_rows_.size()); ++j) three_marks[j] = false;
  }
  for (std::size_t k = 0; k < three_rows_.size(); ++k) {
    const Root& r = three_rows_[k];
    const bool gap = k > 0 && r.step != three_rows_[k - 1].step + 1 && r.step != three_rows_[k - 1].step;
    out << (first ? "" : k == 0 || gap ? "\n" : "") << "3-ipp," << r.period << "," << r.t2 << "," << r.energy << ","
        << r.stable << ",0," << three_marks[k] << "\n";
    first = false;
  }
  for (std::size_t b = 0; b < branches.size(); ++b) {
    out << (first ? "" : "\n");
    first = false;
    for (std::size_t k = 0; k < branches[b].size(); ++k) {
      const Root& r = branches[b][k];
      out << "2-ipp," << r.period << "," << r.t2 << "," << r.energy << "," << r.stable << "," << b + 1 << ","
          << marks[b][k] << "\n";
    }
  }
}

// (T over the roots' span of periods, log E over their decades: the frame
// of a plot of the whole table, or of a zoom on it.)
std::vector<std::vector<bool>> EqualStepMarks(const std::vector<std::vector<FepTable::Root>>& branches,
                                              bool short_at_middle) {
  double t_lo = INFINITY, t_hi = 0.0, e_lo = INFINITY, e_hi = 0.0;
  for (const auto& branch : branches) {
    for (const FepTable::Root& r : branch) {
      t_lo = std::min(t_lo, r.period);
      t_hi = std::max(t_hi, r.period);
      if (r.energy > 0.0) {
        e_lo = std::min(e_lo, r.energy);
        e_hi = std::max(e_hi, r.energy);
      }
    }
  }
  const double decades = e_hi > e_lo ? std::max(std::log10(e_hi / e_lo), 0.1) : 1.0;
  const double t_span = t_hi > t_lo ? t_hi - t_lo : 1.0;
  constexpr double kMarkStep = 0.09;  // of the frame (0.06 made chains of markers on steep branches)
  std::vector<std::vector<bool>> marks;
  for (const auto& branch : branches) {
    marks.emplace_back(branch.size(), false);
    // Each stretch of one stability (drawn as a series of its own) marked
    // from its first point, then at equal steps.
    double since = kMarkStep;
    std::vector<double> at(branch.size(), 0.0);  // each point's length from its stretch's start
    for (std::size_t k = 0; k < branch.size(); ++k) {
      if (k > 0) {
        const FepTable::Root &r = branch[k], &p = branch[k - 1];
        const double dy = r.energy > 0.0 && p.energy > 0.0 ? std::log10(r.energy / p.energy) / decades : 0.0;
        const double step = std::hypot((r.period - p.period) / t_span, dy);
        since += step;
        at[k] = at[k - 1] + step;
        if (r.stable != p.stable) {
          since = kMarkStep;
          at[k] = 0.0;
        }
      }
      // (Not at a stretch's last point: at a change of stability the next
      // stretch's first mark was beside it, and at a branch's end an open
      // circle read as a grazing one.)
      if (since >= kMarkStep) {
        marks.back()[k] = true;
        since = 0.0;
      }
    }
    // A stretch shorter than a step marked at its middle, not its start:
    // Fig. 18's steep (1, 1) pieces, 0.1 s wide, read as a stray marker and
    // a stray dash above it.
    if (!short_at_middle) continue;
    for (std::size_t start = 0, k = 1; k <= branch.size(); ++k) {
      if (k < branch.size() && branch[k].stable == branch[k - 1].stable) continue;
      const double length = at[k - 1];
      if (length < kMarkStep && k - start > 2) {
        std::size_t middle = start;
        for (std::size_t j = start; j < k; ++j) {
          marks.back()[j] = false;
          if (std::abs(at[j] - 0.5 * length) < std::abs(at[middle] - 0.5 * length)) middle = j;
        }
        marks.back()[middle] = true;
      }
      start = k;
    }
  }
  return marks;
}

std::string ContactTimeRange(const Context& c, double lo, double hi) {
  hi = std::max(hi, c.b.gap);
  std::ostringstream os;
  os << "set yrange [" << lo - 0.08 * (hi - lo) << ":" << hi + 0.12 * (hi - lo) << "]\n";
  return os.str();
}

double NiceStep(double lo, double hi, int ticks) {
  const double raw = std::max(hi - lo, 1e-300) / std::max(ticks, 1);
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0}) {
    if (m * decade >= raw) return m * decade;
  }
  return 10.0 * decade;
}

double EnergyTop(std::vector<double> energies) {
  NSMODAL_CHECK(!energies.empty());
  const auto mid = energies.begin() + static_cast<long>(energies.size() / 2);
  std::nth_element(energies.begin(), mid, energies.end());
  return 30.0 * *mid;
}

namespace {

std::optional<Orbit> ZoneEndBetween(const Atlas& atlas, std::size_t k, long j) {
  const auto& at = atlas.one.at;
  if (j < 0 || static_cast<std::size_t>(j) >= at.size()) return std::nullopt;
  const Orbit& o = at[k].front().orbit;
  const Orbit& next = at[static_cast<std::size_t>(j)].front().orbit;
  if (!o.admissible || next.admissible) return std::nullopt;
  const double lo = std::min(o.period, next.period), hi = std::max(o.period, next.period);
  for (const Transition& t : atlas.transitions) {
    if ((t.kind != TransitionKind::kModal && t.kind != TransitionKind::kGrazing) || t.period <= lo || t.period >= hi) {
      continue;
    }
    Orbit end = o;
    end.period = t.period;
    end.energy = t.energy;
    return end;
  }
  return std::nullopt;
}

}  // namespace

std::optional<Orbit> ZoneEndBefore(const Atlas& atlas, std::size_t k) {
  return ZoneEndBetween(atlas, k, static_cast<long>(k) - 1);
}

std::optional<Orbit> ZoneEndAfter(const Atlas& atlas, std::size_t k) {
  return ZoneEndBetween(atlas, k, static_cast<long>(k) + 1);
}

std::string BridgeLook() { return "with vectors arrowstyle 1"; }  // (style::ChartSetup's)

std::pair<double, double> TwoTickValues(double lo, double hi) {
  const double step = TwoTicksStep(lo, hi);
  return {std::ceil(lo / step) * step, std::floor(hi / step) * step};
}

std::string OneTick(double at) {
  std::ostringstream os;  // (not "(" + ...: GCC 12's -Wrestrict false positive on it)
  os << "(" << Num(at) << ")";
  return os.str();
}

std::string TwoTicks(double lo, double hi) {
  const auto [first, last] = TwoTickValues(lo, hi);
  std::ostringstream os;
  os << "(" << first << ", " << last << ")";
  return os.str();
}

double TwoTicksStep(double lo, double hi) {
  for (int ticks = 3; ticks < 12; ++ticks) {
    const double step = NiceStep(lo, hi, ticks);
    if (std::floor(hi / step) - std::ceil(lo / step) >= 1) return step;
  }
  return NiceStep(lo, hi, 12);
}

// (Not the grid's end: past the admissible orbits it holds potential ones
// only, and the right of the chart would be empty.)
double PeriodTop(const Context& c, bool one_only) {
  double top = 0.0;
  for (const Sweep* sweep : {&c.atlas.one, &c.atlas.two}) {
    if (one_only && sweep != &c.atlas.one) continue;
    for (const auto& list : sweep->at) {
      for (const OrbitRecord& r : list) {
        if (r.orbit.admissible) top = std::max(top, r.orbit.period);
      }
    }
  }
  if (top <= 0.0) return c.periods.back();
  return std::min(c.periods.back(), 2.0 * std::ceil(0.5 * 1.05 * top));
}

std::string EnergyAxes(const Context& c, bool one_only) {
  const auto [lo, hi] = EnergyRange(c);
  std::ostringstream os;
  os << "set logscale y\n" << LogTics("y", lo, hi) << "set yrange [" << lo << ":" << hi << "]\n"
     << "set xlabel 'period T (s)'\nset ylabel 'energy E (J)'\nset xrange [0:" << PeriodTop(c, one_only) << "]\n"
     << "set key below maxrows 4\n";
  return os.str();
}

void WriteBridges(std::ostream& out, const std::vector<Bridge>& bridges) {
  out << "T,t2,energy_min,energy_max,s_begin,s_end,kind\n";
  for (const Bridge& br : bridges) {
    out << br.period << "," << br.t2 << "," << br.energy_min << "," << br.energy_max << "," << br.s_begin << ","
        << br.s_end << "," << (IsGrazing(br) ? "grazing" : "period-doubling") << "\n";
  }
}


std::pair<double, double> AddOrbitsNear(const Context& c, double t, double w, FepTable& table,
                                        std::pair<double, double>* periods) {
  double lo = INFINITY, hi = -INFINITY, t_lo = INFINITY, t_hi = -INFINITY;
  SweepOptions admissible_only;
  admissible_only.stability = StabilityPolicy::kAdmissible;
  for (int j = 0; j <= 400; ++j) {
    const double p = t - w + 2 * w * j / 400.0;
    for (int impacts : {1, 2}) {
      for (const OrbitRecord& r : OrbitsAt(c.b, p, impacts, admissible_only)) {
        if (!r.orbit.admissible) continue;
        table.Add(j, r.orbit, r.stability);
        lo = std::min(lo, r.orbit.energy);
        hi = std::max(hi, r.orbit.energy);
        t_lo = std::min(t_lo, r.orbit.period);
        t_hi = std::max(t_hi, r.orbit.period);
      }
    }
  }
  if (periods) *periods = {t_lo, t_hi};
  return {lo, hi};
}

void TransitionLines(Context& c, const std::string& name, bool all, std::ostream& body, Plot& plot) {
  report::ResultFile tr(c.dir, name);
  tr << "T,kind,energy\n";
  std::map<TransitionKind, std::vector<double>> at;
  for (const Transition& t : c.transitions) {
    tr << t.period << "," << ToString(t.kind) << "," << t.energy << "\n";
    at[t.kind].push_back(t.period);
  }
  tr.Commit();
  const auto [lo, hi] = EnergyRange(c);
  const std::string block = name.substr(0, name.find('.'));
  body << VerticalLines(block + "_singular", at[TransitionKind::kSingular], lo, hi);
  // T_S above each singular transition's line, outside the frame (the
  // families crowd the top of the frame, where the energy diverges), in one
  // row: each label centred on its line, or ending at it (right) or starting
  // at it (left) where its neighbours need the room, the fewest off centre
  // (a label is 4 % of the axis wide in the column PDF, where the text is
  // largest against the axis, with 1 % between labels). Stacked in rows,
  // readers found the labels hard to follow; one label shared by close
  // lines read as naming one line. Rows only where no such placing fits
  // (more than 8 lines, or lines closer than a label's width and a gap).
  const double axis = PeriodTop(c, all), w = 0.04 * axis, gap = 0.01 * axis;
  const std::vector<double>& singular = at[TransitionKind::kSingular];
  const std::size_t n = singular.size();
  std::vector<int> best;  // per line: 0 centred, 1 right (ending at it), 2 left (starting at it)
  if (n > 0 && n <= 8) {
    int best_cost = 1 << 30;
    std::vector<int> choice(n, 0);
    for (long code = 0; code < static_cast<long>(std::pow(3.0, static_cast<double>(n))); ++code) {
      long rest = code;
      int cost = 0;
      bool fits = true;
      double end = -INFINITY;
      for (std::size_t k = 0; k < n && fits; ++k) {
        choice[k] = static_cast<int>(rest % 3);
        rest /= 3;
        cost += choice[k] != 0;
        const double from = choice[k] == 0 ? singular[k] - 0.5 * w : choice[k] == 1 ? singular[k] - w : singular[k];
        fits = from >= end + gap;
        end = from + w;
      }
      if (fits && cost < best_cost) {
        best_cost = cost;
        best = choice;
      }
    }
  }
  if (!best.empty()) {
    const char* align[] = {"center", "right", "left"};
    for (std::size_t k = 0; k < n; ++k) {
      body << "set label 'T_S' at " << singular[k] << ", graph 1 " << align[best[k]] << " offset 0, 0.8\n";
    }
    body << "set tmargin 2.6\n";
  } else if (n > 0) {
    std::vector<double> last;  // each row's last label
    for (const double t : singular) {
      std::size_t row = 0;
      while (row < last.size() && t - last[row] < w + gap) ++row;  // the lowest row with room
      if (row == last.size()) last.push_back(t);
      last[row] = t;
      body << "set label 'T_S' at " << t << ", graph 1 center offset 0, " << 0.8 + 1.1 * static_cast<double>(row) << "\n";
    }
    body << "set tmargin " << 1.5 + 1.1 * static_cast<double>(last.size()) << "\n";
  }
  // T_G beside each grazing circle, to its left (the stability changes that
  // follow a graze are marked to its right), clear of the circle (1.8: at
  // -0.8 characters the label touched it in the column PDF); where the
  // bridges are labelled (B1, ...), the key's circle says it.
  for (const Transition& t : c.transitions) {
    if (all && t.kind == TransitionKind::kGrazing && t.energy < hi) {
      body << "set label 'T_G' at " << t.period << ", " << t.energy << " right offset -1.2, 0 front\n";
    }
  }
  plot.Add("$" + block + "_singular using 1:2", With("singular"), "singular, T_S",
           static_cast<long>(at[TransitionKind::kSingular].size()));
}

void TransitionMarks(const Context& c, const std::string& name, bool all, Plot& plot) {
  // Each mark at its energy, counted if in the frame. A linear modal
  // transition too: a point (the grazing linear mode's energy, where the
  // 1-ipp branch ends on it), not a line across all energies.
  const auto [lo, hi] = EnergyRange(c);
  std::map<TransitionKind, long> count;
  for (const Transition& t : c.transitions) count[t.kind] += t.energy >= lo && t.energy <= hi;
  for (const auto& [kind, role, title] :
       {std::tuple<TransitionKind, const char*, const char*>{TransitionKind::kGrazing, "grazing", "grazing, T_G"},
        {TransitionKind::kModal, "modal_point", "modal, k T_i"},
        {TransitionKind::kMultiplierPlusOne, "multiplier_plus_one", "{/Symbol m} through +1"},
        {TransitionKind::kMultiplierMinusOne, "multiplier_minus_one", "{/Symbol m} through -1"}}) {
    if (!all && kind != TransitionKind::kGrazing) continue;
    plot.Add("'" + name + "' using 1:(strcol(2) eq '" + ToString(kind) + "' ? $3 : 1/0)", With(role), title,
             count[kind]);
  }
}

}  // namespace nsmodal::report
