// nsmodal figures: the paper's Figs. 2-15 redrawn from the project's own
// computations. Each figure is DIR/figNN_name.{csv,png,svg} (+ the gnuplot
// scripts), the CSV holding exactly what is drawn. Trajectory CSVs hold one
// orbit per block, blocks separated by a blank line (gnuplot's convention for
// separate curves). Which orbits are drawn is chosen from the scene's own
// transitions, so another system gets the corresponding figures.
#include <algorithm>
#include <cmath>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <tuple>
#include <array>

#include "nsmodal/figures.h"

#include "chart.h"
#include "nsmodal/admissibility.h"
#include "nsmodal/atlas.h"
#include "nsmodal/figure_subjects.h"
#include "nsmodal/stability.h"
#include "nsmodal/bridge.h"
#include "nsmodal/check.h"
#include "nsmodal/error.h"
#include "nsmodal/flow.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/parallel.h"
#include "nsmodal/return_map.h"
#include "nsmodal/trajectory.h"
#include "nsmodal/transitions.h"
#include "nsmodal/two_impact.h"
#include "nsmodal/gnuplot.h"
#include "nsmodal/output.h"
#include "nsmodal/style.h"

namespace nsmodal::report {
namespace {


// The part of x_c above d filled, keyed "x_c > d: NC3 fails" where there is
// one: `spec` the data of the samples `tr` (OrbitTrajectory's), above d by
// more than 1e-6 d (a graze's round-off is not an excess).
void AddExcess(Plot& plot, const Context& c, const std::string& spec, const Eigen::MatrixXd& tr) {
  const long above = (tr.col(1 + c.contact).array() > c.b.gap + 1e-6 * std::abs(c.b.gap)).count();
  plot.Add(spec, "with filledcurves above y=" + std::to_string(c.b.gap) + " " + style::Look("excess"),
           Xc(c) + " > d: NC3 fails", above);
}

// A chart of x_c(t) over one period of one orbit (Figs. 2, 5, 9) drawn as
// `role`: the orbit's samples to DIR/NAME.csv, the obstacle at d, the part
// of x_c above d filled (an NC3 failure is seen, not read off a number).
// `setup` is gnuplot set-up before the plot, `marks` more layers after it.
void DrawOneOrbit(Context& c, const std::string& name, const Orbit& o, const char* role, const std::string& setup,
                  const std::function<void(Plot&)>& marks, const std::string& note) {
  report::ResultFile out(c.dir, name + ".csv");
  WriteTrajectoryHeader(out.stream(), c);
  const Eigen::MatrixXd tr = OrbitTrajectory(c.b, o, kSamples);
  WriteTrajectory(out.stream(), "x", o.period, tr);
  out.Commit();
  const std::string xc = std::to_string(TCol()) + ":" + std::to_string(XCol(c, c.contact));
  std::ostringstream body;
  // (The range the orbit's and d's, 5 % beyond, not rounded out to the
  // ticks: Fig. 5's -1.5 to 1.5 left a band below its -1.1 empty.)
  body << "set xlabel 'time t (s)'\nset ylabel '" << XcLabel(c) << "'\nset key below\nset autoscale yfix\nset xrange [0:"
       << o.period << "]\n" << setup;
  Plot plot;
  AddExcess(plot, c, "'" + name + ".csv' using " + xc, tr);
  plot.Add("'' using " + xc, With(role), Xc(c) + "(t), T = " + Num(o.period))
      .Add(std::to_string(c.b.gap), With("obstacle"), "obstacle d");
  // Its impact at t = 0, again at T (each orbit is computed from one).
  ImpactMarks(c, {0.0, o.period})(plot);
  if (marks) marks(plot);
  Draw(c, name, body.str() + plot.str(), note);
}


// Layers circling the points (t, d) where an orbit grazes the obstacle.
std::function<void(Plot&)> GrazeMarks(const Context& c, const std::vector<double>& times) {
  const double d = c.b.gap;
  const std::string title = "graze: " + Xc(c) + " = d, v_{" + std::to_string(c.contact + 1) + "} = 0";
  return [times, d, title](Plot& plot) {
    for (std::size_t k = 0; k < times.size(); ++k) Mark(plot, times[k], d, "grazing", k ? "" : title);
  };
}

// Fig. 2: a motion from ker A_2 that fails NC2 and NC3 (the paper's Fig. 2):
// t2 dotted, x_c(t2) != d circled, the excess above d filled.
void Figure2(Context& c) {
  const std::optional<Orbit> pick = NotAdmissibleExample(c.b, c.atlas);
  if (!pick) {
    c.log << "  fig02: no potential 2-ipp root off T/2 whose kernel motion fails NC3 visibly; skipped\n";
    return;
  }
  const double t2 = pick->times[0];
  Eigen::VectorXd y = pick->y0;
  Flow(c.b, t2, y);
  const double x_t2 = ContactPosition(c.b, y);
  std::ostringstream setup;
  setup << "set arrow from " << t2 << ", graph 0 to " << t2 << ", graph 1 nohead " << style::Look("time_mark") << "\n"
        << "set label 't_2' at " << t2 << ", graph 1 offset 0.5, -1\n";
  std::ostringstream note;
  note << "T = " << pick->period << ", t2 = " << t2 << ", x_c(t2) = " << x_t2 << ", x_c exceeds d by up to "
       << pick->max_excess;
  DrawOneOrbit(c, "fig02_not_admissible", *pick, "orbit_not_admissible", setup.str(),
               [&](Plot& plot) { Mark(plot, t2, x_t2, "mark", Xc(c) + "(t_2) {/Symbol \\271} d: NC2 fails"); }, note.str());
}

// Fig. 3: 1-ipp energies, admissible zones coloured by stability,
// transitions: singular ones (T_S) as vertical lines, modal and grazing ones
// (T_G) and the stability changes as marks on the branch; an inset on each
// stable stretch too short to see.
void Figure3(Context& c) {
  report::ResultFile out(c.dir, "fig03_one_impact.csv");
  out << "T,energy,potential,admissible,stable,max_multiplier\n";
  long potential = 0, stable = 0, unstable = 0;
  // (Each admissible stretch drawn to the modal or grazing transition it
  // ends on: a row at the transition, step k's stability, no multiplier.)
  auto row = [&](const Orbit& o, const std::optional<Stability>& stability, bool end) {
    out << o.period << "," << o.energy << "," << o.potential << "," << o.admissible << "," << IsStable(stability) << ",";
    if (stability && !end) out << stability->max_modulus;
    out << "\n";
  };
  for (std::size_t k = 0; k < c.atlas.one.at.size(); ++k) {
    const Orbit& o = c.atlas.one.at[k].front().orbit;
    const std::optional<Stability>& stability = c.atlas.one.at[k].front().stability;
    if (const std::optional<Orbit> end = ZoneEndBefore(c.atlas, k)) row(*end, stability, true);
    row(o, stability, false);
    if (const std::optional<Orbit> end = ZoneEndAfter(c.atlas, k)) row(*end, stability, true);
    potential += o.potential;
    (IsStable(stability) ? stable : unstable) += o.admissible;
  }
  std::ostringstream body;
  body << EnergyAxes(c, true);
  // The transition lines under the family, their marks over it.
  Plot plot;
  TransitionLines(c, "fig03_transitions.csv", true, body, plot);
  plot.Add("'fig03_one_impact.csv' using 1:($3 == 1 ? $2 : 1/0)", With("potential"), "potential", potential)
      .Add("'' using 1:($4 == 1 && $5 == 1 ? $2 : 1/0)", With("one_stable"), "admissible, stable", stable)
      .Add("'' using 1:($4 == 1 && $5 == 0 ? $2 : 1/0)", With("one_unstable"), "admissible, unstable", unstable);
  TransitionMarks(c, "fig03_transitions.csv", true, plot);
  out.Commit();
  Draw(c, "fig03_one_impact_energy", body.str() + StableStretchInsets(c, plot));
}

// Fig. 4: the linear modal transition: admissible on one side, not on the
// other, the grazing linear mode at the transition.
void Figure4(Context& c, const ModalPick& m) {
  if (m.side == 0) {
    c.log << "  fig04: no modal transition bounds an admissible zone; skipped\n";
    return;
  }
  const double eps = std::min(0.02 * m.period, 0.5 * m.width);
  report::ResultFile out(c.dir, "fig04_modal_transition.csv");
  WriteTrajectoryHeader(out.stream(), c);
  const Orbit in = OneImpactOrbit(c.b, m.period + m.side * eps), beyond = OneImpactOrbit(c.b, m.period - m.side * eps);
  const Orbit mode = GrazingMode(c.b, ModeOf(c.b, m.period), m.period);
  WriteTrajectory(out.stream(), "admissible", in.period, OrbitTrajectory(c.b, in, kSamples));
  const Eigen::MatrixXd mode_tr = OrbitTrajectory(c.b, mode, kSamples);
  WriteTrajectory(out.stream(), "modal", mode.period, mode_tr);
  const Eigen::MatrixXd beyond_tr = OrbitTrajectory(c.b, beyond, kSamples);
  WriteTrajectory(out.stream(), "not_admissible", beyond.period, beyond_tr);
  // The mode's grazes inside the period (t / T), circled as Figs. 5 and 9
  // circle theirs: its samples at d (to 1e-6 d) with none higher beside
  // them.
  const long xc_col = 1 + c.contact;
  const double tol = 1e-6 * std::max(1.0, std::abs(c.b.gap));
  std::vector<double> grazes;
  for (long r = 1; r + 1 < mode_tr.rows(); ++r) {
    const double x = mode_tr(r, xc_col);
    if (std::abs(x - c.b.gap) <= tol && x >= mode_tr(r - 1, xc_col) && x >= mode_tr(r + 1, xc_col) &&
        (grazes.empty() || mode_tr(r, 0) / mode.period - grazes.back() > 0.01)) {
      grazes.push_back(mode_tr(r, 0) / mode.period);
    }
  }
  std::ostringstream body;
  body << "set xlabel 'normalised time t / T'\nset ylabel '" << XcLabel(c) << "'\nset key below\nset autoscale yfix\n";
  const std::string xc = std::to_string(XCol(c, c.contact));
  std::ostringstream in_title, mode_title, beyond_title;  // (periods to 4 digits: the note has them all)
  // The admissible orbit as the 1-ipp branch draws it there: stable dark
  // and solid, unstable light and dashed.
  const bool stable = OrbitStability(c.b, in).stable;
  in_title << "T = " << Num(in.period) << " (admissible, " << (stable ? "stable" : "unstable") << ")";
  mode_title << "T = " << Num(m.period) << " (grazing linear mode)";
  // (Not "x_c > d: not admissible": the excess's own entry says x_c > d.)
  beyond_title << "T = " << Num(beyond.period) << " (not admissible)";
  // The orbit beyond drawn as Fig. 2 draws a motion that is not an orbit:
  // grey and solid, its excess above d filled.
  Plot plot;
  AddExcess(plot, c, "'fig04_modal_transition.csv' using (strcol(1) eq 'not_admissible' ? $3/$2 : 1/0):" + xc,
            beyond_tr);
  plot.Add("'' using (strcol(1) eq 'admissible' ? $3/$2 : 1/0):" + xc, With(stable ? "orbit" : "orbit_unstable"),
           in_title.str())
      .Add("'' using (strcol(1) eq 'modal' ? $3/$2 : 1/0):" + xc, With("limit"), mode_title.str())
      .Add("'' using (strcol(1) eq 'not_admissible' ? $3/$2 : 1/0):" + xc, With("orbit_not_admissible"),
           beyond_title.str());
  plot.Add(std::to_string(c.b.gap), With("obstacle"), "obstacle d");
  // The impact at t = 0, again at T (t / T = 0 and 1), filled as Figs. 2, 5
  // and 9 fill theirs; the mode's grazes circled.
  ImpactMarks(c, {0.0, 1.0})(plot);
  GrazeMarks(c, grazes)(plot);
  body << plot.str();
  out.Commit();
  std::ostringstream note;
  note << "modal transition T = " << m.period << ", admissible at " << in.period << ", not at " << beyond.period;
  Draw(c, "fig04_modal_transition", body.str(), note.str());
}


// Fig. 5: the 1-ipp orbit at a grazing transition, the one whose bridge
// Figs. 13-15 draw (Fig. 9 shows the other kind, a graze off T/2).
void Figure5(Context& c) {
  const Bridge* paper = PaperBridge(c.atlas);
  if (!paper) {
    c.log << "  fig05: no grazing transition in the sweep; skipped\n";
    return;
  }
  const Bridge& br = *paper;
  std::ostringstream note;
  note << "T_G = " << br.period << ", graze at t = " << br.t2;
  // (Black: a grazing orbit is a family's limit, as in Figs. 13-15.)
  DrawOneOrbit(c, "fig05_grazing_transition", OneImpactOrbit(c.b, br.period), "limit", "",
               GrazeMarks(c, {br.t2}), note.str());
}

// The 2-ipp sweep's roots are drawn on every k-th period of its grid, k
// chosen so that at most kDrawnRoots are drawn: the grid's step is far
// below a pixel of the charts (4000 periods on 900 px), and a light SVG and
// PDF need a few thousand marks, not tens of thousands. Their CSVs hold
// every root, with a column `drawn`.
constexpr long kDrawnRoots = 8000;
int DrawEvery(const Sweep& sweep) {
  long roots = 0;
  for (const auto& list : sweep.at) roots += static_cast<long>(list.size());
  return static_cast<int>(std::max<long>(1, (roots + kDrawnRoots - 1) / kDrawnRoots));
}

// Fig. 6: det A_2(t2, T) against t2 for T = 1..10, with its roots.
void Figure6(Context& c) {
  report::ResultFile out(c.dir, "fig06_det_a2.csv");
  report::ResultFile roots(c.dir, "fig06_roots.csv");
  out << "T,t2,det\n";
  roots << "T,t2,half_period\n";
  std::vector<std::array<double, 2>> range(11, {INFINITY, -INFINITY});  // det's range at each T
  std::vector<std::array<long, 2>> found(11, {0, 0});                   // roots off T/2, trivial roots
  for (int period = 1; period <= 10; ++period) {
    for (int j = 1; j < 1000; ++j) {
      const double t2 = period * j / 1000.0, det = MatrixA(c.b, {t2}, period).determinant();
      out << period << "," << t2 << "," << det << "\n";
      range[period] = {std::min(range[period][0], det), std::max(range[period][1], det)};
    }
    out << "\n";
    for (double r : TwoImpactRoots(c.b, period)) {
      roots << period << "," << r << "," << AtHalfPeriod(r, period) << "\n";
      ++found[period][AtHalfPeriod(r, period)];
    }
  }
  std::ostringstream body;
  // Ten small panels: labels shared (y on the left column, x on the bottom
  // row), ticks at 0 and T and about three on det, the two kinds of root
  // keyed once each below the panels (by the first panel that draws one).
  body << "set multiplot layout 2,5 margins 0.1, 0.97, 0.17, 0.91 spacing 0.065, 0.15\n"
       << "set format y '%g'\nset ytics scale 0.5\nset key horizontal\n"
       << "set nonlinear y via sgn(y) * sqrt(abs(y)) inverse sgn(y) * y**2\n";
  bool keyed[2] = {false, false};
  for (int period = 1; period <= 10; ++period) {
    const std::string at = "($1 == " + std::to_string(period) + " && $3 == ";
    Plot plot;
    plot.Unkeyed("'fig06_det_a2.csv' using ($1 == " + std::to_string(period) + " ? $2 : 1/0):3", With("function"));
    for (int trivial : {1, 0}) {
      const std::string spec = "'fig06_roots.csv' using " + at + std::to_string(trivial) + " ? $2 : 1/0):(0)";
      const char* role = trivial ? "trivial_root" : "root";
      if (!keyed[trivial] && found[period][trivial] > 0) {
        body << "set key at screen " << (trivial ? 0.3 : 0.7) << ", screen 0.02 center bottom\n";
        plot.Add(spec, With(role), trivial ? "trivial root t_2 = T/2" : "root t_2 {/Symbol \\271} T/2");
        keyed[trivial] = true;
      } else {
        plot.Unkeyed(spec, With(role));
      }
    }
    // det A_2 >= 0 here (its roots are double, touching 0; the samples'
    // values below 0 are rounding, 1e-32): the axis from just below 0, so
    // that the roots sit on its foot and a near-root reads as one; in
    // sign(det) sqrt|det| (on a linear axis, the humps between the roots at
    // T = 4 and 5, 0.5 under ends of 11, were 1 % of the panel's height and
    // a root could not be told from a near-root; as a square root a double
    // root is a V through 0). Ticks at 0, about an eighth and about the top.
    const double hi = range[period][1], step = NiceStep(0.0, hi, 2), low = NiceStep(0.0, hi / 4.0, 2);
    // (t2 from 4 % before 0 to 4 % past T: the roots at 0 and T sat on the
    // frame, and the neighbours' labels "T" and "0" ran together in the
    // column PDF, "1 0 2".)
    body << "set title 'T = " << period << " s'\nset xrange [" << -0.04 * period << ":" << 1.04 * period
         << "]\nset xtics (0, " << period << ")\n"
         << "set xlabel '" << (period > 5 ? "t_2 (s)" : "") << "'\nset ylabel '" << (period % 5 == 1 ? "det A_2 (√ axis)" : "")
         << "'\nset yrange [" << -0.0036 * hi << ":" << 1.1236 * hi << "]\nset ytics (0, " << low << ", "
         << std::floor(hi / step) * step << ")\n"
         << plot.str();
  }
  body << "unset multiplot";
  out.Commit();
  roots.Commit();
  Draw(c, "fig06_det_a2", body.str());
  // The roots as curves in the (T, t2) plane, from the atlas's 2-ipp sweep:
  // the trivial line t2 = T/2 (eq. 26, a root at every T) and the others,
  // admissible or not; the same roots as Fig. 7's map, uncoloured.
  report::ResultFile curves(c.dir, "fig06_root_curves.csv");
  curves << "T,t2,admissible,branch,alone\n";
  // The roots joined into branches along T (TwoImpactBranches, as the
  // frequency-energy plots join them: on steep stretches the roots of
  // consecutive periods lie far apart, a string of dots read as isolated
  // roots), each a line through all its roots (34,000 for paper.toml: a
  // line through every 5th broke into dashes on steep stretches).
  std::vector<FepTable::Root> found_roots;
  for (std::size_t k = 0; k < c.atlas.two.at.size(); ++k) {
    for (const OrbitRecord& r : c.atlas.two.at[k]) {
      if (!r.orbit.potential || IsHalfPeriodRoot(r.orbit)) continue;
      // (`stable` carries admissibility here: the branches do not use it.)
      found_roots.push_back({static_cast<int>(k), r.orbit.period, r.orbit.times[0], r.orbit.energy, r.orbit.admissible});
    }
  }
  long other = 0, admissible = 0, alone = 0, alone_other = 0;
  const std::vector<std::vector<FepTable::Root>> branches = TwoImpactBranches(std::move(found_roots));
  // The rows of one branch (TwoImpactBranches joins a root to a branch only
  // within 0.05 of its extrapolation: no straight segment across a jump).
  // Column `alone` marks the roots of a run too short to draw a line.
  for (std::size_t b = 0; b < branches.size(); ++b) {
    const std::vector<FepTable::Root>& branch = branches[b];
    for (std::size_t i = 0, run = 0; i < branch.size(); i += run) {
      // A run of one admissibility shorter than 3 roots (a line through one
      // or two roots is not seen): its roots drawn as points.
      // So is an admissible run under 1 % of the frame's diagonal (those of
      // Fig. 6 at T = 35.5, lines a reader did not find).
      run = 1;
      while (i + run < branch.size() && branch[i + run].stable == branch[i].stable) ++run;
      double t_lo = INFINITY, t_hi = -INFINITY, s_lo = INFINITY, s_hi = -INFINITY;
      for (std::size_t k = i; k < i + run; ++k) {
        t_lo = std::min(t_lo, branch[k].period);
        t_hi = std::max(t_hi, branch[k].period);
        s_lo = std::min(s_lo, branch[k].t2 / branch[k].period);
        s_hi = std::max(s_hi, branch[k].t2 / branch[k].period);
      }
      // (The diagonal's test for the admissible runs only: the others are
      // context, and as points they clumped into grey blobs on the curves.)
      const bool short_run =
          run < 3 || (branch[i].stable && std::hypot((t_hi - t_lo) / c.periods.back(), s_hi - s_lo) < 0.01 * std::sqrt(2.0));
      for (std::size_t k = i; k < i + run; ++k) {
        const FepTable::Root& r = branch[k];
        curves << r.period << "," << r.t2 << "," << r.stable << "," << b + 1 << "," << short_run << "\n";
        (r.stable ? admissible : other) += 1;
        (r.stable ? alone : alone_other) += short_run;
      }
    }
    curves << "\n";
  }
  curves.Commit();
  std::ostringstream plane;
  // t2 / T in [0, 1]: the roots fill the frame (t2 < T leaves half of a
  // (T, t2) frame empty), the trivial line is t2 / T = 1/2, drawn over
  // them; the linear modal transitions, where branches end, as short
  // vertical lines.
  // (No vertical grid: it looked like the k T_i lines.)
  // (The key in two columns of three: in one column of six it took a fifth
  // of the column PDF's height.)
  plane << "set xlabel 'period T (s)'\nset ylabel 'second impact time t_2 / T'\nset key below maxrows 3\n"
        << "unset grid\nset grid ytics lt 1 lw 0.5 lc rgb '" << style::Colour("grid") << "'\n"
        << "set xrange [0:" << c.periods.back() << "]\nset yrange [0:1]\n";
  // Every multiple k T_i of a linear period in the frame (where the 1-ipp
  // orbits meet the linear modes, the 2-ipp root curves end or are cut).
  std::vector<double> modal;
  for (const double period : c.b.Periods()) {
    for (int k = 1; period > 0.0 && k * period <= c.periods.back(); ++k) modal.push_back(k * period);
  }
  plane << VerticalLines("modal", modal, 0.0, 1.0);
  Plot plot;
  plot.Add("$modal using 1:2", With("modal"), "multiples k T_i", static_cast<long>(modal.size()))
      .Add("'fig06_root_curves.csv' using 1:($3 == 0 ? $2 / $1 : 1/0)", With("root_cloud_other", "lines"),
           "root, not admissible", other)
      .Add("'' using 1:($3 == 1 ? $2 / $1 : 1/0)", With("root_curve"), "root, admissible", admissible);
  // (The runs of one or two roots, points: keyed, they had read as noise.)
  plot.Add("'fig06_root_curves.csv' using 1:($3 == 0 && $5 == 1 ? $2 / $1 : 1/0)", With("root_cloud_other"),
           "short run, not admissible", alone_other)
      .Add("'fig06_root_curves.csv' using 1:($3 == 1 && $5 == 1 ? $2 / $1 : 1/0)", With("root"),
           "short run, admissible", alone);
  plot.Add("0.5", With("two_half"), "trivial root t_2 = T/2");
  Draw(c, "fig06_root_curves", plane.str() + plot.str());
}

// Fig. 7: the 2-ipp energies as a map over (T, t2): each potential root a
// mark, grey where the orbit is not admissible, coloured by its energy
// (log scale, the energy map) where it is, filled stable, open unstable;
// the line t2 = T/2 (the trivial root). The paper draws E over (T, t2) in
// 3-D; from above, the t2 <-> T - t2 symmetry (the same orbit started at
// the other impact) is the mirror symmetry about t2 = T/2.
void Figure7(Context& c) {
  report::ResultFile out(c.dir, "fig07_two_impact.csv");
  out << "T,t2,energy,potential,admissible,stable,max_multiplier,half_period,drawn\n";
  // Every admissible root drawn, the others on every k-th period
  // (DrawEvery): thinned too, the admissible ones of short runs were lost
  // (T = 6.54-6.55 on paper.toml).
  const int every = DrawEvery(c.atlas.two);
  const auto [lo, hi] = EnergyRange(c);
  long grey = 0, stable = 0, unstable = 0, below = 0, above = 0;
  double e_lo = INFINITY, e_hi = 0.0;
  for (std::size_t k = 0; k < c.atlas.two.at.size(); ++k) {
    for (const OrbitRecord& r : c.atlas.two.at[k]) {
      const Orbit& o = r.orbit;
      if (!o.potential) continue;
      const bool drawn = o.admissible || k % every == 0;
      out << o.period << "," << o.times[0] << "," << o.energy << "," << o.potential << "," << o.admissible << ","
          << IsStable(r.stability) << ",";
      if (r.stability) out << r.stability->max_modulus;
      out << "," << IsHalfPeriodRoot(o) << "," << drawn << "\n";
      if (!drawn) continue;
      if (!o.admissible) {
        ++grey;
      } else {
        (IsStable(r.stability) ? stable : unstable) += 1;
        e_lo = std::min(e_lo, o.energy);
        e_hi = std::max(e_hi, o.energy);
        below += o.energy < lo;
        above += o.energy > hi;
      }
    }
  }
  out.Commit();
  // The bar over the frequency-energy plots' energies: roots beyond take
  // its end's colour, the end labelled <= or >= (on paper.toml 120 of the
  // 3,162 admissible roots lie above 23.6 J, up to 2.1e6 J).
  e_lo = std::max(e_lo, lo);
  e_hi = std::min(std::max(e_hi, 2 * e_lo), hi);
  std::ostringstream body;
  // t2 / T in [0, 1], as Fig. 6's root curves; one mark per admissible root
  // coloured by its energy (their stability is Fig. 8's: filled and open
  // marks this dense could not be told apart), the line t2 = T/2 over the
  // grey marks and under the coloured ones (over them, it hid the colour of
  // the dilated branch's marks).
  body << "set xlabel 'period T (s)'\nset ylabel 'second impact time t_2 / T'\nset key below\n"
       << "set xrange [0:" << PeriodTop(c) << "]\nset yrange [0:1]\n"
       // (The bar's title above it: beside it, the column PDF cut it at the
       // canvas's edge. Its ends named too, to three digits: the lowest and
       // highest energies drawn.)
       << style::Palette("energy", "") << "set tmargin 2.2\nset label 'E (J)' at graph 1.065, graph 1.05 centre\nset logscale cb\n"
       << LogTics("cb", e_lo, e_hi, true, {below > 0, above > 0}) << "set cbrange [" << e_lo << ":" << e_hi << "]\n";
  Plot plot;
  plot.Add("'fig07_two_impact.csv' using 1:($9 == 1 && $5 == 0 ? $2 / $1 : 1/0)", With("root_cloud_other", "points", style::Colour("grey_faint")),
           "potential, not admissible", grey)
      .Add("0.5", With("two_half"), "t_2 = T/2")
      .Add("'fig07_two_impact.csv' using 1:($9 == 1 && $5 == 1 ? $2 / $1 : 1/0):3", style::WithPalette("map_stable"),
           "admissible (colour: its energy)", stable + unstable);
  Draw(c, "fig07_two_impact_energy", body.str() + plot.str(),
       "the energy's colours from " + Num(e_lo, 3) + " to " + Num(e_hi, 3) + " J; " + std::to_string(below) +
           " admissible roots below, " + std::to_string(above) + " above");
}

// Fig. 8: the combined frequency-energy plot.
void Figure8(Context& c) {
  FepTable table;
  table.AddAtlas(c.atlas);
  const std::string body = FepChart(c, table, "fig08_fep.csv", "fig08_bridges.csv", "fig08_transitions.csv");
  std::ostringstream note;
  for (std::size_t k = 0; k < c.bridges.size(); ++k) {
    note << (k ? "; " : "") << "B" << k + 1 << " " << (IsGrazing(c.bridges[k]) ? "grazing" : "period-doubling")
         << " at T = " << c.bridges[k].period;
  }
  Draw(c, "fig08_fep", body, note.str());
}

// Fig. 9: a 1-ipp orbit with two grazes, admissible as a 3-ipp orbit too.
void Figure9(Context& c) {
  const std::optional<TwoGrazes> g = TwoGrazesExample(c.b, c.atlas);
  if (!g) {
    c.log << "  fig09: no grazing orbit admissible as a 3-ipp orbit in the sweep; skipped\n";
    return;
  }
  const Bridge& br = *g->bridge;
  std::ostringstream note;
  note << "T = " << br.period << ", grazes at t = " << br.t2 << " and " << br.period - br.t2
       << ", NC2 residual as a 3-ipp orbit " << g->three.nc2_residual;
  DrawOneOrbit(c, "fig09_two_grazes", g->one, "limit", "", GrazeMarks(c, {br.t2, br.period - br.t2}),
               note.str());
}

// The phase sections of Figs. 10, 12, 14: (x_other, x_c, v_c), the paper's
// (x_1, x_2, v_2). A one-dof system has no x_other: time takes its place.
// A family of orbits is a surface there (a nonsmooth mode, or a bridge's
// continuum): each orbit one scan of it, all with the same rows.
// Each orbit's shade is the parameter that runs along the family (T, an
// arclength); it is drawn as the position along the family, from 0 at its
// start to 1 at its end (the one meaning of the family colour map), the
// colour bar naming the parameter's values at both ends.
//
// (Samples per flight of a surface's scans: a surface of 40 scans of 2
// flights is 4,800 facets, a light SVG and PDF, smooth at the charts' size.)
constexpr int kSurfaceSamples = 60;
struct SectionFamily {
  std::string parameter;  // what the shade is, e.g. "period T (s)"
  std::vector<std::pair<double, Eigen::MatrixXd>> orbits;  // (shade, OrbitTrajectory)
  // false: the orbits drawn as curves, not as a surface (a family whose
  // outer orbits would hide the inner ones behind a surface).
  bool surface = true;
  // OrbitTrajectory's samples per flight of each orbit.
  int samples = kSurfaceSamples;
  // The shades' range mapped to the colour bar (default: the orbits').
  std::optional<std::pair<double, double>> range = std::nullopt;
  // Each orbit's stability, in order (curves only: dashed where unstable);
  // empty: not drawn.
  std::vector<bool> stable = {};
};
struct SectionCurve {
  std::string title;
  const char* role;  // style.toml series
  std::vector<Eigen::MatrixXd> trajectories;  // OrbitTrajectory of each orbit
};

// The columns of a section CSV (WriteTrajectory) that the sections draw, as
// gnuplot's column numbers: x_other (time for one dof), x_c, v_c.
struct SectionColumns {
  std::string u, w, v;
};

// [a, b] padded by 5 % on each side, its top at least `beyond`.
std::string PaddedRange(double a, double b, double beyond = -INFINITY) {
  std::ostringstream os;
  os << "[" << a - 0.05 * (b - a) << ":" << std::max(b + 0.05 * (b - a), beyond) << "]";
  return os.str();
}

// The axes of a section's (x_c, v_c) projection, its obstacle line x_c = d:
// the data's ranges (autoscaling would extend them to the next ticks), x_c
// past the obstacle by 8 % of its range (its line clear of the frame).
std::string ContactProjectionAxes(const Context& c, const double lo[3], const double hi[3]) {
  std::ostringstream os;
  os << "set xlabel '" << DofLabel("x", c.contact, "m") << "'\nset ylabel '" << DofLabel("v", c.contact, "m/s")
     << "'\nset xtics " << NiceStep(lo[1], hi[1], 4) << "\nset ytics " << NiceStep(lo[2], hi[2], 5) << "\nset xrange "
     // (Past d by 0.14 of the span: at 0.08 the impact states on x_c = d
     // lay a few pixels from the frame.)
     << PaddedRange(lo[1], hi[1], c.b.gap + 0.14 * (hi[1] - lo[1])) << "\nset yrange " << PaddedRange(lo[2], hi[2])
     << "\nset arrow from " << c.b.gap << ", graph 0 to " << c.b.gap << ", graph 1 nohead " << style::Look("obstacle")
     << "\nset label 'd' at " << c.b.gap << ", graph 1 center offset 0, 0.7\n";
  return os.str();
}

// The `using` of a section's (x_c, v_c) samples at x_c = d (to 1e-9 of it):
// the states just before and just after each impact, shaded by column 2;
// with `shade`, those of the orbit at that place along the family only.
std::string ImpactStates(const Context& c, const std::string& w, const std::string& v,
                         std::optional<double> shade = std::nullopt) {
  std::ostringstream os;
  os << "(abs($" << w << " - " << c.b.gap << ") <= " << 1e-9 * std::max(1.0, std::abs(c.b.gap));
  if (shade) os << " && abs($2 - " << *shade << ") < 1e-5";
  os << " ? $" << w << " : 1/0):" << v << ":2";
  return os.str();
}

// A family drawn as curves (SectionFamily::surface false) in two
// projections: (x_other, x_c) with the obstacle x_c = d a line, and (x_c,
// v_c), where the jump of v_c at x_c = d is a gap between each orbit's
// ends; each orbit shaded by its position along the family (the colour bar
// on the right), the curves (a family's limit) over them, one key below.
// (In 3-D, a few space curves and no surface gave no depth cue: a tangle.)
// NAME.csv as DrawSection's.
void DrawProjections(Context& c, const std::string& name, const std::string& parameter, const std::string& bar,
                     const SectionColumns& col, const std::vector<SectionCurve>& curves, const double lo[3],
                     const double hi[3], const std::vector<std::pair<double, bool>>& orbits, const std::string& note) {
  const std::string &u = col.u, &w = col.w, &v = col.v;
  std::ostringstream body;
  body << "set multiplot\n" << style::Palette("family", parameter) << bar << "set cbrange [0:1]\n"
       // (The key below both panels in columns of three rows, 0.22 high:
       // "horizontal maxcols 2" set its five entries in one column, which
       // needed 0.3 and left a white band in the PNG; the top at 0.95, the
       // d label above the right panel clear of the canvas's edge.)
       << "set bmargin at screen 0.22\nset tmargin at screen 0.95\n"
       // (The right panel, where the impact states are, 0.28 wide: at 0.24,
       // beside the left's 0.34, a reader found it narrow in the column.)
       << "set lmargin at screen 0.1\nset rmargin at screen 0.40\nunset colorbox\n"
       << "set key at screen 0.5, screen 0.005 center bottom vertical maxrows 3\n"
       << "set xlabel '" << (c.b.n > 1 ? DofLabel("x", c.other, "m") : std::string("t (s)")) << "'\nset ylabel '"
       << DofLabel("x", c.contact, "m") << "'\nset xtics " << NiceStep(lo[0], hi[0], 4) << "\nset ytics "
       << NiceStep(lo[1], hi[1], 4) << "\nset xrange " << PaddedRange(lo[0], hi[0]) << "\nset yrange "
       << PaddedRange(lo[1], hi[1], c.b.gap + 0.08 * (hi[1] - lo[1])) << "\n";
  // The curves (a family's limit) under the family: at x_c = d, where the
  // orbits' v_c jumps, the limit covered the jumps.
  // The obstacle under everything on the left (over them, its dashes hid
  // the orbits' arcs along x_c = d), keyed in its place below.
  Plot left, right;
  left.Unkeyed(std::to_string(c.b.gap), With("obstacle"));
  for (std::size_t k = 0; k < curves.size(); ++k) {
    const std::string index = "'" + name + ".csv' index " + std::to_string(k + 1) + " using ";
    left.Add(index + u + ":" + w, With(curves[k].role), curves[k].title, static_cast<long>(curves[k].trajectories.size()));
    right.Unkeyed(index + w + ":" + v, With(curves[k].role));
  }
  // Each orbit a layer at its place on the palette, dashed where unstable
  // (WithMapped: a layer coloured point by point restarts the dash at every
  // segment), the unstable ones keyed in black.
  bool dashed = false;
  for (const auto& [shade, stable] : orbits) {
    std::ostringstream pick;
    pick << "(abs($2 - " << shade << ") < 1e-5 ? $";
    const std::string look = style::WithMapped(stable ? "family_orbit" : "family_orbit_unstable", "", shade);
    left.Unkeyed("'" + name + ".csv' index 0 using " + pick.str() + u + " : 1/0):" + w, look);
    right.Unkeyed("'" + name + ".csv' index 0 using " + pick.str() + w + " : 1/0):" + v, look);
    dashed = dashed || !stable;
  }
  if (dashed) {
    left.KeyOnly(With("family_orbit"), "stable orbit").KeyOnly(With("family_orbit_unstable"), "unstable orbit");
  }
  left.KeyOnly(With("obstacle"), "obstacle " + Xc(c) + " = d");
  // The impact states on the right, just before and just after each impact
  // (the samples at x_c = d, to 1e-9 of it), in their orbit's colour: where
  // each orbit's loop breaks (keyed in black). An unstable orbit's open, as
  // its line is dashed, under the stable ones' filled dots: the orbits'
  // impact velocities lie close, and a layer of filled dots hid one orbit's
  // under the others' (Fig. 12, a reader found); a ring shows through.
  for (const bool stable : {false, true}) {
    bool any = false;
    for (const auto& [shade, orbit_stable] : orbits) {
      if (orbit_stable != stable) continue;
      right.Unkeyed("'" + name + ".csv' index 0 using " + ImpactStates(c, w, v, shade),
                    style::WithPalette(stable ? "impact_state" : "impact_state_unstable"));
      any = true;
    }
    if (any && !dashed) {
      left.KeyOnly(With("impact_state", "points", style::Colour("black")), "impact state (right)");
    } else if (any) {
      left.KeyOnly(With(stable ? "impact_state" : "impact_state_unstable", "points", style::Colour("black")),
                   stable ? "impact, stable orbit (right)" : "impact, unstable orbit (right)");
    }
  }
  body << left.str() << "unset key\nset lmargin at screen 0.54\nset rmargin at screen 0.82\n"
       << "set colorbox user origin screen 0.845, screen 0.22 size screen 0.025, screen 0.68\n"
       << ContactProjectionAxes(c, lo, hi) << right.str() << "unset multiplot";
  Draw(c, name, body.str(), note);
}

// Draws NAME: left, the family as a shaded surface (viridis by shade,
// depth-sorted, with a colour bar), the curves, the obstacle plane x_c = d
// (translucent) and the floor on the data, seen so that the surface's two
// edges on the plane (just before and just after the impact) are apart;
// right, the (x_c, v_c) projection, where the jump of v_c at x_c = d is a gap
// between the ends of each orbit. NAME.csv holds the family (curve
// "family", column 2 the shade; scans separated by a blank line, gnuplot's
// first dataset), then after two blank lines one block per curve.
void DrawSection(Context& c, const std::string& name, const SectionFamily& family,
                 const std::vector<SectionCurve>& curves, const std::string& note) {
  // The three coordinates' columns in an OrbitTrajectory (t, x, v); in the
  // CSV each is TCol() further on (WriteTrajectory's label and T first).
  const int cols[3] = {c.b.n > 1 ? 1 + c.other : 0, 1 + c.contact, 1 + c.b.n + c.contact};
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  double s_lo = INFINITY, s_hi = -INFINITY;
  for (const auto& [shade, tr] : family.orbits) {
    s_lo = std::min(s_lo, shade);
    s_hi = std::max(s_hi, shade);
  }
  if (family.range) std::tie(s_lo, s_hi) = *family.range;
  NSMODAL_CHECK(s_hi > s_lo);  // (the callers draw families of several orbits)
  auto extend = [&](const Eigen::MatrixXd& tr) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], tr.col(cols[k]).minCoeff());
      hi[k] = std::max(hi[k], tr.col(cols[k]).maxCoeff());
    }
  };
  report::ResultFile out(c.dir, name + ".csv");
  WriteTrajectoryHeader(out.stream(), c);
  for (const auto& [shade, tr] : family.orbits) {
    // (OrbitTrajectory's rows per flight: samples + 1.)
    WriteTrajectory(out.stream(), "family", (shade - s_lo) / (s_hi - s_lo), tr, family.samples + 1);
    extend(tr);
  }
  for (const SectionCurve& curve : curves) {
    out << "\n";
    for (const Eigen::MatrixXd& tr : curve.trajectories) {
      WriteTrajectory(out.stream(), "curve", 0.0, tr);
      extend(tr);
    }
  }
  out.Commit();
  // The colour bar: the position along the family, its ends named by the
  // parameter's values (short: a long bar label is cut in the column PDF).
  std::ostringstream bar;
  bar << FamilyBarTics(s_lo, s_hi);
  const SectionColumns col{std::to_string(TCol() + cols[0]), std::to_string(TCol() + cols[1]),
                           std::to_string(TCol() + cols[2])};
  const std::string &u = col.u, &w = col.w, &v = col.v;
  if (!family.surface) {
    std::vector<std::pair<double, bool>> orbits;  // each orbit's place along the family, and its stability
    for (std::size_t k = 0; k < family.orbits.size(); ++k) {
      orbits.push_back({(family.orbits[k].first - s_lo) / (s_hi - s_lo), family.stable.empty() || family.stable[k]});
    }
    DrawProjections(c, name, family.parameter, bar.str(), col, curves, lo, hi, orbits, note);
    return;
  }
  std::ostringstream body;
  // (No bar label: it would run into the projection's; the map's one
  // meaning, the position along the family, is said above the bar.)
  body << "set multiplot\nset size 0.54, 1\nset origin 0, 0\n" << style::Palette("family", "")
       << bar.str() << "set cbrange [0:1]\nset colorbox user origin screen 0.51, screen 0.25 size screen 0.02, screen 0.5\n"
       << "set label 1 '" << family.parameter << "' at screen 0.52, screen 0.78 center\n"
       // About four ticks per 3-D axis: more collide at the column PDF's size.
       << InnerTics("x", lo[0], hi[0], 5) << InnerTics("y", lo[1], hi[1], 5) << "set ztics " << NiceStep(lo[2], hi[2], 4)
       << "\n"
       // (The plane's place on its axis named: the inner ticks stop short of
       // it, and a reader asked where x_c = d was.)
       << "set ytics add ('d' " << c.b.gap << ")\n"
       // (The tick labels off their axes, the axes' labels past them: on
       // the axes, the lines struck "0.5", "0", "-0.5" through.)
       << "set xtics offset -0.3, -0.4\nset ytics offset 0.6, -0.3\n"
       << "set xlabel '" << (c.b.n > 1 ? DofLabel("x", c.other, "m") : std::string("t (s)")) << "' offset -1.5, -0.6\nset ylabel '"
       << DofLabel("x", c.contact, "m") << "' offset 2.5, -0.5\nset zlabel '" << DofLabel("v", c.contact, "m/s") << "' rotate offset 2.5, 0\n"
       // (The data's ranges, set: the overlay of the limit curve below maps
       // onto the same frame.)
       << "set xrange [" << lo[0] << ":" << hi[0] << "]\nset yrange [" << lo[1] << ":" << hi[1] << "]\nset zrange ["
       << lo[2] << ":" << hi[2] << "]\n"
       // (The box at 0.9 of its size: at 1 the key's last row lay on the
       // plane's top corner.)
       << "set view 62, 35, 0.9\nset xyplane relative 0\nset key at screen 0.02, screen 0.99 left top\n"
       // (A faint light from the viewer: the shading tells the surface's
       // folds apart, and the colours stay within 15 % of the bar's.)
       // (Each facet's border traced in its own colour: no white seams
       // between facets in the PDFs.)
       << "set pm3d depthorder border retrace lighting primary 0.15 specular 0.0\n"
       << "$plane << EOD\n"
       << lo[0] << "," << c.b.gap << "," << lo[2] << "\n" << lo[0] << "," << c.b.gap << "," << hi[2] << "\n\n"
       << hi[0] << "," << c.b.gap << "," << lo[2] << "\n" << hi[0] << "," << c.b.gap << "," << hi[2] << "\nEOD\n"
       // The plane's outline, drawn as the obstacle is elsewhere.
       << "$edge << EOD\n" << lo[0] << "," << c.b.gap << "," << lo[2] << "\n" << lo[0] << "," << c.b.gap << "," << hi[2]
       << "\n" << hi[0] << "," << c.b.gap << "," << hi[2] << "\n" << hi[0] << "," << c.b.gap << "," << lo[2] << "\n"
       << lo[0] << "," << c.b.gap << "," << lo[2] << "\nEOD\n";
  Plot surface("splot");
  surface.Unkeyed("'" + name + ".csv' index 0 using " + u + ":" + w + ":" + v + ":2", "with pm3d")
      .Unkeyed("$plane using 1:2:3", "with pm3d fillcolor rgb '" + style::Colour("plane") + "'")
      .Unkeyed("$edge using 1:2:3", With("obstacle"));
  // The plane keyed by a swatch of its grey (a surface has no key sample;
  // keyed by its dashed outline, it read as a line, not the grey plane).
  surface.KeySwatch("with boxes fs solid 1.0 noborder lc rgb '" + style::Colour("plane") + "'",
                    "obstacle " + Xc(c) + " = d (the plane)");
  // The projection: every other orbit of a family of more than 8 (the
  // curves overlap: 11 orbits of two loops were 22 curves in a band).
  const std::string every = family.orbits.size() > 8 ? " every :2" : "";
  Plot projection;
  projection.Unkeyed("'" + name + ".csv' index 0" + every + " using " + w + ":" + v + ":2", style::WithPalette("family_curve"));
  // Its impact states, filled in their orbit's colour (as Fig. 12's).
  projection.Unkeyed("'" + name + ".csv' index 0" + every + " using " + ImpactStates(c, w, v),
                     style::WithPalette("impact_state"));
  surface.KeyOnly(With("impact_state", "points", style::Colour("black")), "impact state (right)");
  // A family's limit (the grazing orbit or mode, on the surface's edge,
  // which the depth-sorted surface hid) drawn again over the 3-D panel: the
  // same frame, ranges and view, nothing but the curve.
  Plot over("splot");
  for (std::size_t k = 0; k < curves.size(); ++k) {
    const std::string index = "'" + name + ".csv' index " + std::to_string(k + 1) + " using ";
    surface.Add(index + u + ":" + w + ":" + v, With(curves[k].role), curves[k].title,
                static_cast<long>(curves[k].trajectories.size()));
    if (std::string(curves[k].role) == "limit") over.Unkeyed(index + u + ":" + w + ":" + v, With(curves[k].role));
    projection.Unkeyed(index + w + ":" + v, With(curves[k].role));
  }
  body << surface.str();
  if (!over.empty()) {
    body << "unset border\nunset tics\nunset xlabel\nunset ylabel\nunset zlabel\nunset colorbox\nunset key\nunset grid\n"
         << "unset label 1\n" << over.str() << "set border\nset tics\nset grid\n";
  }
  // (Margins above and right: the d label and the last tick label had
  // met the canvas edge in the column PDF.)
  body << "unset label 1\nset size 0.41, 1\nset origin 0.59, 0\nset tmargin 2\nset rmargin 2.5\nunset pm3d\nunset colorbox\nunset key\n"
       << ContactProjectionAxes(c, lo, hi) << projection.str() << "unset multiplot";
  Draw(c, name, body.str(), note);
}

// Fig. 10: the 1-ipp nonsmooth mode next to the modal transition of Fig. 4.
void Figure10(Context& c, const ModalPick& m) {
  if (m.side == 0) {
    c.log << "  fig10: no modal transition bounds an admissible zone; skipped\n";
    return;
  }
  const Orbit mode = GrazingMode(c.b, ModeOf(c.b, m.period), m.period);
  // Orbits across the zone, stopping where the energy passes 4 times the
  // mode's (towards a singular transition it diverges).
  SectionFamily family{"T (s)", {{m.period, OrbitTrajectory(c.b, mode, kSurfaceSamples)}}};
  for (int k = 1; k <= 24; ++k) {
    const Orbit o = OneImpactOrbit(c.b, m.period + m.side * m.width * k / 25.0);
    if (!o.admissible || o.energy > 4.0 * mode.energy) break;
    family.orbits.emplace_back(o.period, OrbitTrajectory(c.b, o, kSurfaceSamples));
  }
  std::ostringstream note;
  note << family.orbits.size() - 1 << " 1-ipp orbits, T from " << m.period << " to "
       << (family.orbits.empty() ? m.period : family.orbits.back().first);
  DrawSection(c, "fig10_one_impact_mode", family,
              {{"grazing linear mode", "limit", {OrbitTrajectory(c.b, mode, kSamples)}}}, note.str());
}

// The point of the branch's run nearest to the fraction f of its arclength
// from the start (the continuation's steps are adaptive: orbits taken at
// equal steps of the run would bunch where the steps are short).
const BranchPoint& AtArclength(const ModeBranch& m, double f) {
  const double s0 = m.branch[m.run.front()].arclength, total = std::abs(m.branch[m.run.back()].arclength - s0);
  std::size_t best = m.run.front();
  for (std::size_t k : m.run) {
    if (std::abs(std::abs(m.branch[k].arclength - s0) - f * total) <
        std::abs(std::abs(m.branch[best].arclength - s0) - f * total)) {
      best = k;
    }
  }
  return m.branch[best];
}

// Figs. 11-12: the 2-ipp nonsmooth mode through the grazing linear mode of
// the shortest period T_i, taken at T = 3 T_i with t2 = T_i (a root: the mode
// grazes d at 0, T_i and 2 T_i), followed by continuation.
void Figures11And12(Context& c) {
  const ModeBranch m = TwoImpactModeBranch(c.b);
  if (m.run.empty()) {
    c.log << "  fig11-12: " << m.why_not << "; skipped\n";
    return;
  }
  const std::vector<BranchPoint>& branch = m.branch;
  const std::vector<std::size_t>& run = m.run;
  const int mode = m.mode;
  const double period = m.period;
  report::ResultFile out(c.dir, "fig11_two_impact_mode.csv");
  out << "index,T,t";
  for (int i = 1; i <= c.b.n; ++i) out << ",x" << i;
  for (int i = 1; i <= c.b.n; ++i) out << ",v" << i;
  out << ",t2,energy,arclength,stable\n";
  const Orbit linear = GrazingMode(c.b, mode, period);
  std::vector<double> orbit_shades;  // each orbit's arclength (index 0: the mode), then its fraction
  std::vector<bool> orbit_stable;
  auto write = [&](int index, const Orbit& o, double arclength) {
    const Eigen::MatrixXd tr = OrbitTrajectory(c.b, o, kSamples);
    const bool stable = index > 0 && OrbitStability(c.b, o).stable;
    orbit_shades.push_back(arclength);
    orbit_stable.push_back(stable);
    for (long r = 0; r < tr.rows(); ++r) {
      out << index << "," << o.period;
      for (long k = 0; k < tr.cols(); ++k) out << "," << tr(r, k);
      out << "," << (o.times.empty() ? 0.0 : o.times[0]) << "," << o.energy << "," << arclength << "," << stable << "\n";
    }
    out << "\n";
  };
  // The arclength from the branch's start, the grazing mode.
  const double s0 = branch[run.front()].arclength, s1 = branch[run.back()].arclength;
  write(0, linear, 0.0);
  const int curves = 4;  // (eight, dashed, tangled where x_c < 0: no orbit could be followed)
  std::ostringstream summary;
  for (int j = 1; j <= curves; ++j) {
    const BranchPoint& p = AtArclength(m, static_cast<double>(j) / curves);
    const Orbit o = TwoImpactOrbitAt(c.b, p.t2, p.period);
    write(j, o, std::abs(p.arclength - s0));
    if (j == curves) summary << "last: T = " << o.period << ", t_2 = " << o.times[0];
  }
  for (double& shade : orbit_shades) shade /= std::max(std::abs(s1 - s0), 1e-300);
  double tmin = INFINITY, tmax = -INFINITY;
  for (std::size_t k : run) {
    tmin = std::min(tmin, branch[k].period);
    tmax = std::max(tmax, branch[k].period);
  }
  std::ostringstream body;
  // The colour bar: the position along the family, its ends named by the
  // arclength from the grazing mode (short: a long label is cut in print).
  std::ostringstream bar;
  bar << FamilyBarTics(0.0, std::abs(s1 - s0));
  // Against t / T: the orbits' periods differ (T spans the family), their
  // first impacts at 0 and T align; each orbit's second impact t2 circled in
  // its colour.
  const std::string arc = "($" + std::to_string(6 + 2 * c.b.n) + " / " + std::to_string(std::abs(s1 - s0)) + ")";
  const std::string xc = std::to_string(XCol(c, c.contact));
  // (The orbits' range, not rounded out to the ticks: -2 to 1.5 left a
  // quarter of the height empty.)
  body << "set xlabel 'time over the period t / T'\nset ylabel '" << XcLabel(c) << "'\nset key below\nset autoscale yfix\n"
       << style::Palette("family", "arclength {/Symbol s} (s)") << bar.str() << "set cbrange [0:1]\n"
       << "set xrange [0:1]\n";
  // Each orbit solid where stable, dashed where not (keyed in black: their
  // colour is their place along the family); the impacts at 0 and T filled.
  const std::string stable_col = "$" + std::to_string(7 + 2 * c.b.n);
  Plot plot;
  // The obstacle under everything (over the t2 circles, its dashes ran
  // through them), keyed in its place below.
  plot.Unkeyed(std::to_string(c.b.gap), With("obstacle"));
  const long stable_orbits = std::count(orbit_stable.begin() + 1, orbit_stable.end(), true);
  if (stable_orbits > 0) plot.KeyOnly(With("family_orbit"), "stable orbit");
  if (stable_orbits < curves) plot.KeyOnly(With("family_orbit_unstable"), "unstable orbit");
  // (Each orbit a layer at its place on the palette, WithMapped: a layer
  // coloured point by point restarts the dash at every segment, and a
  // dashed orbit looked solid.)
  for (std::size_t j = 1; j < orbit_shades.size(); ++j) {
    plot.Unkeyed("'fig11_two_impact_mode.csv' using ($1 == " + std::to_string(j) + " ? $3 / $2 : 1/0):" + xc,
                 style::WithMapped(orbit_stable[j] ? "family_orbit" : "family_orbit_unstable", "", orbit_shades[j]));
  }
  plot.Add("'fig11_two_impact_mode.csv' using ($3 / $2):(strcol(1) eq '0' ? $" + xc + " : 1/0)", With("limit"),
           "grazing linear mode")
      // (Keyed in black: the circle's colour is its orbit's.)
      .KeyOnly(With("impact_map", "points", style::Colour("black")), "second impact t_2");
  // (Each circle on a white disc: the orbits' arcs along d ran through it.)
  const std::string t2_at = "'fig11_two_impact_mode.csv' every ::0::0 using ($1 > 0 ? $" + std::to_string(4 + 2 * c.b.n) +
                            " / $2 : 1/0):(" + std::to_string(c.b.gap) + ")";
  plot.Unkeyed(t2_at, With("ring_ground"))
      .Unkeyed(t2_at + ":" + arc, style::WithPalette("impact_map"))
      .KeyOnly(With("obstacle"), "obstacle d");
  ImpactMarks(c, {0.0, 1.0})(plot);  // (the first impact, at 0 and T: t / T = 0 and 1)
  body << plot.str();
  out.Commit();
  std::ostringstream note;
  note << "from the grazing mode at T = 3 T_i = " << period << " (T_i = " << c.b.Periods()[mode]
       << ", the shortest linear period) to " << summary.str()
       << "; T spans [" << tmin << ", " << tmax << "]";
  Draw(c, "fig11_two_impact_orbits", body.str(), note.str());
  // Fig. 12: the branch's orbits in the section: Fig. 11's, in its colours
  // (41 made a tangle where no orbit could be followed; 11 too).
  // (The grazing mode, s = 0, is the black curve; the colour bar over the
  // whole arclength, as Fig. 11's. Curves sampled finely: 2 x 400 points.)
  SectionFamily family{"arclength {/Symbol s} (s)", {}};
  family.samples = 2 * kSamples;
  family.range = std::pair<double, double>{0.0, std::abs(s1 - s0)};
  for (int j = 1; j <= curves; ++j) {
    const BranchPoint& p = AtArclength(m, static_cast<double>(j) / curves);
    family.orbits.emplace_back(std::abs(p.arclength - s0),
                               OrbitTrajectory(c.b, TwoImpactOrbitAt(c.b, p.t2, p.period), family.samples));
    family.stable.push_back(orbit_stable[static_cast<std::size_t>(j)]);
  }
  // As curves in two projections: the family winds inwards from the
  // grazing mode, and a surface showed its outer orbits alone (the inner
  // ones behind them).
  family.surface = false;
  DrawSection(c, "fig12_two_impact_mode", family,
              {{"grazing linear mode", "limit", {OrbitTrajectory(c.b, linear, kSamples)}}}, "");
}

// Figs. 13-15: the bridge.
void Figures13To15(Context& c) {
  const Bridge* br = PaperBridge(c.atlas);
  if (!br) {
    c.log << "  fig13-15: no grazing transition in the sweep; skipped\n";
    return;
  }
  const double t = br->period;
  // Fig. 13: x_c(t) along the continuum.
  {
    report::ResultFile out(c.dir, "fig13_bridge_orbits.csv");
    WriteTrajectoryHeader(out.stream(), c);
    const Orbit one = OneImpactOrbit(c.b, t);
    const Eigen::MatrixXd one_tr = OrbitTrajectory(c.b, one, kSamples);
    WriteTrajectory(out.stream(), "one", t, one_tr);
    const Eigen::MatrixXd shifted = ShiftTrajectory(one_tr, t - br->t2, t);
    WriteTrajectory(out.stream(), "one_shifted", t, shifted);
    // s = 0.1, 0.3, 0.5 s_end: orbit s_end - s is orbit s shifted by T/2
    // (Fig. 14's symmetry), so the half of the bridge holds every orbit once.
    // Each orbit's x_c less the grazing orbit's, at its own samples: the
    // lower panel. (The grazing orbit's x_c between its samples, linear, of
    // a trajectory sampled 100 times as finely as the drawn ones: steps of
    // T / 20000 err by about 1e-7 d against differences of 1e-2 d.)
    report::ResultFile diff(c.dir, "fig13_bridge_differences.csv");
    diff << "curve,t,dx\n";
    const long col = 1 + c.contact;
    const Eigen::MatrixXd fine = OrbitTrajectory(c.b, one, 100 * kSamples);
    auto difference = [&](const std::string& label, const Eigen::MatrixXd& tr) {
      const double* ts = fine.col(0).data();
      const long n = fine.rows();
      for (long r = 0; r < tr.rows(); ++r) {
        const double time = tr(r, 0);
        const long k = std::clamp(static_cast<long>(std::upper_bound(ts, ts + n, time) - ts), 1L, n - 1);
        const double h = fine(k, 0) - fine(k - 1, 0), f = h > 0.0 ? (time - fine(k - 1, 0)) / h : 0.0;
        diff << label << "," << time << "," << tr(r, col) - ((1 - f) * fine(k - 1, col) + f * fine(k, col)) << "\n";
      }
      diff << "\n";
    };
    difference("one_shifted", shifted);
    // (The upper panel's x_c range: the orbits'.)
    double x_lo = one_tr.col(col).minCoeff(), x_hi = one_tr.col(col).maxCoeff();
    for (const auto& [label, f] : {std::pair<const char*, double>{"s10", 0.1}, {"s30", 0.3}, {"s50", 0.5}}) {
      const Eigen::MatrixXd tr = OrbitTrajectory(c.b, BridgeOrbit(c.b, *br, f * br->s_end), kSamples);
      WriteTrajectory(out.stream(), label, t, tr);
      difference(label, tr);
      x_lo = std::min(x_lo, tr.col(col).minCoeff());
      x_hi = std::max(x_hi, tr.col(col).maxCoeff());
    }
    diff.Commit();
    std::ostringstream body;
    // The ends of the bridge (the grazing orbit and its shift) black, as in
    // Fig. 14; the three 2-ipp orbits between in the family map's colours at
    // their positions along the half, as Fig. 14 shades them (each keyed:
    // three curves need no colour bar). Below, each orbit less the grazing
    // one: the orbits lie within 0.4 d of each other. One key, under both.
    // (Each orbit's colour the map's at its place, interpolated as Fig. 14's
    // surface: the map's nearest stop had drawn s = 0.3 s_end in the colour
    // Fig. 14's bar gives 0.25.)
    const std::string xc = std::to_string(XCol(c, c.contact));
    // (The panels placed on the canvas, their frames aligned in every
    // format, over one key in three columns at its foot: below the lower
    // panel in one column of seven, it squeezed that panel in the column PDF;
    // their foot over the x labels and the key's band: KeyFoot, the band 0.16
    // of the PNG and 0.25 of the column PDF, whose key has four rows: at
    // 0.19, the PNG had a gap of 45 px over its key), the lower
    // panel 0.4 of their height.
    body << style::Palette("family", "") << "unset colorbox\nset multiplot\nns_foot = " << KeyFoot(0.025, 0.225)
         << "\nns_split = ns_foot + 0.4 * (0.97 - ns_foot - 0.03)\nset lmargin at screen 0.14\n"
         << "set rmargin at screen 0.97\nset bmargin at screen (ns_split + 0.03)\nset tmargin at screen 0.97\nset format x ''\n"
         << "set xlabel ''\nset ylabel '" << XcLabel(c) << "'\nset xrange [0:" << t << "]\n"
         << ContactTimeRange(c, x_lo, x_hi);
    Plot upper("plot", Plot::Keys::kCollected);
    upper.Add("'fig13_bridge_orbits.csv' using (strcol(1) eq 'one' ? $3 : 1/0):" + xc, With("limit"),
              "grazing, s = 0")
        .Add("'' using (strcol(1) eq 'one_shifted' ? $3 : 1/0):" + xc, With("limit_shifted"),
             "shifted by T/2, s = s_{end}");
    std::vector<std::string> roles;
    for (int pct : {10, 30, 50}) {
      roles.push_back(style::WithMapped("orbit", "lines", pct / 50.0));
      upper.Add("'' using (strcol(1) eq 's" + std::to_string(pct) + "' ? $3 : 1/0):" + xc, roles.back(),
                "2-ipp, s = 0." + std::to_string(pct / 10) + " s_{end}");
    }
    upper.Add(std::to_string(c.b.gap), With("obstacle"), "obstacle d");
    // The impacts every orbit of the bridge shares: 0, t2, T (at t2 the
    // grazing orbit's graze, the 2-ipp orbits' second impact).
    ImpactMarks(c, {0.0, br->t2, t})(upper);
    // The lower panel: the differences.
    Plot lower;
    const std::string d = "'fig13_bridge_differences.csv' using (strcol(1) eq '";
    lower.Unkeyed("0", With("limit")).Unkeyed(d + "one_shifted' ? $2 : 1/0):3", With("limit_shifted"));
    for (int pct : {10, 30, 50}) lower.Unkeyed(d + "s" + std::to_string(pct) + "' ? $2 : 1/0):3", roles[(pct - 10) / 20]);
    const std::string x = Xc(c);
    body << upper.str() << "set bmargin at screen ns_foot\nset tmargin at screen ns_split\n"
         // (Short: "x - x(s = 0)" ran into the upper panel's label in the
         // column PDF; the caption says what it is.)
         << "set autoscale y\nset format x '% g'\nset xlabel 'time t (s)'\nset ylabel '{/Symbol D}" << x
         // (Ticks every 0.2 d: at 0.5 d, the panel had three labels.)
         << " (m)'\nset ytics " << NiceStep(-c.b.gap, c.b.gap, 10) << "\n"
         << lower.str() << LegendPanel(0.14) << Plot::Legend(upper.Collected()) << "unset multiplot\n";
    out.Commit();
    std::ostringstream note;
    note << "T_G = " << t << ", the shift " << t - br->t2;
    Draw(c, "fig13_bridge_orbits", body.str(), note.str(), 0.9);
  }
  // Fig. 14: the same in the phase section, with neighbouring 1-ipp orbits.
  {
    // A bridge at grazing is symmetric about s_end / 2 (its orbit there the
    // dilated one, t2 = T/2): orbit s_end - s is orbit s shifted in time
    // (t2 -> T - t2), the same curve in the phase space. Both halves drawn
    // would cover the surface twice and its depth-sorted facets would
    // alternate in stripes: the first half alone where the energies say so.
    std::vector<Orbit> orbits;
    for (int k = 0; k <= 20; ++k) orbits.push_back(BridgeOrbit(c.b, *br, br->s_end * k / 20.0));
    bool symmetric = true;
    for (int k = 0; k <= 10; ++k) {
      // (1e-9: the energies' agreement in the closed form, far below the
      // bridge's energy range, 6 % of E.)
      symmetric = symmetric && std::abs(orbits[k].energy - orbits[20 - k].energy) <= 1e-9 * orbits[k].energy;
    }
    SectionFamily family{"s / s_{end}", {}};
    for (int k = 0; k <= (symmetric ? 10 : 20); ++k) {
      family.orbits.emplace_back(k / 20.0, OrbitTrajectory(c.b, orbits[k], kSurfaceSamples));
    }
    DrawSection(c, "fig14_bridge_section", family,
                {{"grazing 1-ipp orbit (s = 0)", "limit", {OrbitTrajectory(c.b, OneImpactOrbit(c.b, t), kSamples)}}},
                symmetric ? "the bridge's half s <= s_end / 2 (symmetric about it)" : "");
  }
  // Fig. 15: zoom of the frequency-energy plot on the bridge.
  {
    const double w = 0.01 * t;
    report::ResultFile out(c.dir, "fig15_bridge_fep.csv");
    FepTable table;
    const auto [lo, hi] = AddOrbitsNear(c, t, w, table);
    table.Write(out.stream());
    report::ResultFile bo(c.dir, "fig15_bridge.csv");
    WriteBridges(bo.stream(), {*br});
    const double e_lo = std::min(lo, br->energy_min), e_hi = std::max(hi, br->energy_max);
    const double pad = 0.1 * (e_hi - e_lo);
    std::ostringstream body;
    // (The key inside, at the foot's left, under the branches, which fall
    // from left to right: below, in three columns, it had left "grazing"
    // alone at the far right.)
    body << "set xlabel 'period T (s)'\nset ylabel 'energy E (J)'\nset key inside left bottom opaque\n"
         << "set xrange [" << t - w << ":" << t + w << "]\nset yrange [" << e_lo - pad << ":" << e_hi + pad << "]\n"
         << "set label 'B" << (br - c.bridges.data()) + 1 << "' at " << t << ", " << br->energy_max
         << " offset -0.6, 1.1 front\n";
    Plot plot;
    table.AddLayers(plot, "fig15_bridge_fep.csv", "fig15_bridge.csv", 1);
    Mark(plot, t, br->energy_max, "grazing", "grazing, T_G");
    body << plot.str();
    out.Commit();
    bo.Commit();
    std::ostringstream note;
    note << "T_G = " << t << ", E from " << br->energy_min << " to " << br->energy_max;
    Draw(c, "fig15_bridge_fep", body.str(), note.str());
  }
}

// Fig. 17 (beyond the paper): every bridge of the atlas, one zoomed panel
// each, labelled B1, B2, ... as in Fig. 8 with its kind: the branches within
// 1 % of its period (recomputed on 401 periods) and the bridge's vertical
// segment, the energy axis from half the bridge's height below it to half
// above.
void Figure17(Context& c) {
  if (c.bridges.empty()) {
    c.log << "  fig17: no bridge in the atlas; skipped\n";
    return;
  }
  report::ResultFile out(c.dir, "fig17_bridges_fep.csv");
  report::ResultFile bo(c.dir, "fig17_bridges.csv");
  const int n = static_cast<int>(c.bridges.size());
  const int cols = n <= 2 ? n : 2, rows = (n + cols - 1) / cols;
  std::ostringstream body;
  // The panels above one key for all of them (the series of the panels
  // are the same kinds; a key per panel took a third of the height), each
  // titled above its frame; the plot areas placed by hand.
  // (The key's band 0.15 of the height in the column PDF, four rows of two;
  // less where it has three rows of three, as in the PNG: KeyFoot. ns_ch,
  // a row of panels' height.)
  const double key_band = 0.15, cw = 1.0 / cols;
  body << "set multiplot\nset xlabel 'period T (s)' offset 0, 0.3\nset ytics scale 0.5\nns_ch = (1.0 - "
       << KeyFoot(0.0, key_band) << ") / " << rows << ".0\n";
  std::vector<Plot::Entry> entries;
  for (int k = 0; k < n; ++k) {
    const Bridge& br = c.bridges[k];
    const double w = 0.01 * br.period, height = br.energy_max - br.energy_min;
    FepTable table;
    std::pair<double, double> found;
    AddOrbitsNear(c, br.period, w, table, &found);
    // The panel's periods: the admissible orbits found, the bridge inside,
    // 4 % of that span beyond (not all of [T - w, T + w]: B3's orbits took
    // its middle third).
    const double p_lo = std::min(found.first, br.period), p_hi = std::max(found.second, br.period);
    const double margin = 0.04 * std::max(p_hi - p_lo, 1e-3 * br.period);
    const double x_lo = std::isfinite(p_lo) ? p_lo - margin : br.period - w;
    const double x_hi = std::isfinite(p_hi) ? p_hi + margin : br.period + w;
    // (A short stretch at a bridge's foot marked at its middle: under the
    // bridge's cap, B1's unstable one was not seen.)
    table.Write(out.stream(), true);
    out << "\n\n";
    WriteBridges(bo.stream(), {br});
    bo << "\n\n";
    const double x0 = (k % cols) * cw;
    const int row = k / cols;
    // (The energy label on the left column only: the right one's would run
    // into its neighbour.)
    const double lo = br.energy_min - 0.5 * height, hi = br.energy_max + 0.5 * height;
    // (The right column's frame from 0.24 to 0.89 of it, the left one's
    // from 0.3 to 0.95, clear of its energy label: the right one's title,
    // centred over it, reached the canvas's edge in the column PDF.)
    const double left = x0 + (k % cols == 0 || cols == 1 ? 0.3 : 0.24) * cw;
    body << "set lmargin at screen " << left << "\nset rmargin at screen " << left + 0.65 * cw
         << "\nset tmargin at screen (1.0 - " << row + 1 << " * ns_ch + 0.88 * ns_ch)\nset bmargin at screen (1.0 - "
         << row + 1 << " * ns_ch + 0.24 * ns_ch)\n"
         << "set ylabel '" << (k % cols == 0 ? "energy E (J)" : "") << "'\n"
         << "set xtics " << TwoTicksStep(x_lo, x_hi) << "\nset ytics " << NiceStep(lo, hi, 4) << "\n"
         << "set xrange [" << x_lo << ":" << x_hi << "]\nset yrange [" << lo << ":" << hi << "]\n"
         << "set title 'B" << k + 1 << ", " << (IsGrazing(br) ? "grazing" : "period doubling") << ": "
         << std::fixed << std::setprecision(3) << br.period << std::defaultfloat << std::setprecision(6)
         << " s' offset 0, -0.6\n";
    Plot plot("plot", Plot::Keys::kCollected);
    table.AddLayers(plot, "fig17_bridges_fep.csv", "fig17_bridges.csv", 1, k);
    // An end that lies near an admissible orbit of the bridge's period but
    // not on it (within 5 % of the panel's height, apart by more than 1e-6
    // relative): both energies written beside them, the end's to the right
    // and the orbit's to the left (B4's top at 3.160 read as reaching the
    // 2-ipp branch at 3.254).
    body << "unset label\n";
    std::vector<double> at_period;  // the admissible orbits' energies at the bridge's period
    {
      SweepOptions admissible_only;
      admissible_only.stability = StabilityPolicy::kAdmissible;
      for (const int impacts : {1, 2}) {
        for (const OrbitRecord& r : OrbitsAt(c.b, br.period, impacts, admissible_only)) {
          if (r.orbit.admissible) at_period.push_back(r.orbit.energy);
        }
      }
    }
    struct NearEnd {
      double end, nearest;   // the end's energy, the orbit's
      bool grazes = false;   // (the end's orbit grazes d: labelled so, not circled)
    };
    std::vector<NearEnd> near;
    for (const double end : {br.energy_min, br.energy_max}) {
      double nearest = NAN;
      for (const double e : at_period) {
        if (!(std::abs(e - end) >= std::abs(nearest - end))) nearest = e;
      }
      const double gap = std::abs(nearest - end);
      if (gap > 1e-6 * end && gap < 0.05 * (hi - lo)) near.push_back({end, nearest});
    }
    // A grazing bridge's top is the grazing 1-ipp orbit: circled, as on Fig. 8;
    // another bridge's end circled too where its orbit grazes d between its
    // impacts (NC3's margin within 1e-6 d of 0: B4's ends, at 3.160 J, on
    // paper.toml), keyed alike: "grazing orbit". An end near an orbit is
    // not circled but labelled so ("3.160 J, grazing"): the circle, wider
    // than the gap, reached the branch.
    if (IsGrazing(br)) {
      Mark(plot, br.period, br.energy_max, "grazing", "grazing orbit");
    } else {
      double marked = NAN;  // (a symmetric bridge's two ends are one point)
      for (const double s : {br.s_begin, br.s_end}) {
        const Orbit end = BridgeOrbit(c.b, br, s);
        if (std::abs(end.max_excess) > 1e-6 * c.b.gap || std::abs(end.energy - marked) <= 1e-9 * end.energy) continue;
        marked = end.energy;
        const auto labelled = std::find_if(near.begin(), near.end(), [&](const NearEnd& n) {
          return std::abs(n.end - end.energy) <= 1e-9 * end.energy;
        });
        if (labelled != near.end()) {
          labelled->grazes = true;
        } else {
          Mark(plot, br.period, end.energy, "grazing", "grazing orbit");
        }
      }
    }
    for (const NearEnd& n : near) {
      const bool above = n.nearest > n.end;
      // (On two lines where it grazes: on one, it ran past the column PDF's
      // panel.)
      body << std::fixed << std::setprecision(3) << "set label \"" << n.end << " J" << (n.grazes ? "\\ngrazing" : "")
           << "\" at " << br.period << ", " << n.end << " left offset 0.8, " << (above ? (n.grazes ? -1.4 : -0.9) : 0.9)
           << " front\nset label '" << n.nearest << " J' at " << br.period << ", " << n.nearest << " right offset -0.8, "
           // (0.8 of a line off the branch: at 0.6, "3.254 J" sat on B4's
           // 2-ipp circles, which rise to the right under it; at 1.5, on the
           // panel's top edge; at 1, a reader found it floating.)
           << (above ? 0.8 : -0.8) << " front\n" << std::defaultfloat << std::setprecision(6);
    }
    body << plot.str();
    entries.insert(entries.end(), plot.Collected().begin(), plot.Collected().end());
  }
  // The one key by family, as Fig. 8's (each panel collected its own in turn).
  std::stable_sort(entries.begin(), entries.end(), [](const Plot::Entry& a, const Plot::Entry& b) {
    const auto& order = FepTable::kKeyTitles;
    return std::find(order.begin(), order.end(), a.title) < std::find(order.begin(), order.end(), b.title);
  });
  body << LegendPanel(key_band) << Plot::Legend(entries);
  body << "unset multiplot";
  out.Commit();
  bo.Commit();
  Draw(c, "fig17_bridges", body.str());
}

}  // namespace

// Fig. 16 (beyond the paper): an admissible 3-ipp family (figure_subjects.h).
// Left: its energies over T beside the 1-ipp family's, admissible stretch
// solid where stable and dashed where unstable, the rest thin grey, the ends
// of the admissible stretch circled. Right: x_c(t) of the orbit the search
// found, one period, its three impacts at d.
void Figure16(Context& c, const ThreeImpactPick& pick) {
  if (pick.family.empty()) {
    c.log << "  fig16: " << pick.why_not << "; skipped\n";
    return;
  }
  report::ResultFile out(c.dir, "fig16_three_impact_family.csv");
  out << "T,t2,t3,energy,admissible,stable,max_multiplier\n";
  long three[3] = {0, 0, 0};  // not admissible, unstable, stable
  // The stable stretch, a few orbits long, is named where it is (its mean)
  // and zoomed on (its first and last period).
  double s_t = 0.0, s_e = 0.0, s_first = INFINITY, s_last = -INFINITY;
  for (const Orbit& o : pick.family) {
    out << o.period << "," << o.times[0] << "," << o.times[1] << "," << o.energy << "," << o.admissible << ",";
    if (o.admissible) {
      const Stability s = OrbitStability(c.b, o);
      out << (s.defined && s.stable) << "," << s.max_modulus;
      ++three[s.defined && s.stable ? 2 : 1];
      if (s.defined && s.stable) {
        s_t += o.period;
        s_e += o.energy;
        s_first = std::min(s_first, o.period);
        s_last = std::max(s_last, o.period);
      }
    } else {
      out << "0,";
      ++three[0];
    }
    out << "\n";
  }
  report::ResultFile one(c.dir, "fig16_one_impact.csv");
  one << "T,energy,admissible,stable\n";
  // The period axis over the admissible stretch, 15 % of it before and up to
  // 50 % after (where the family, no longer admissible, goes on: the caption
  // follows it there).
  // (Not beyond the family's last orbit and 10 % of the stretch: past it
  // nothing is drawn.)
  const double width = pick.admissible_to - pick.admissible_from;
  const double t_lo = pick.admissible_from - 0.15 * width,
               t_hi = std::min(pick.admissible_to + 0.5 * width, pick.family.back().period + 0.1 * width);
  long one_stable = 0, one_unstable = 0;
  for (const auto& list : c.atlas.one.at) {
    const OrbitRecord& r = list.front();
    if (r.orbit.period >= t_lo && r.orbit.period <= t_hi) {
      one << r.orbit.period << "," << r.orbit.energy << "," << r.orbit.admissible << "," << IsStable(r.stability)
          << "\n";
      (IsStable(r.stability) ? one_stable : one_unstable) += r.orbit.admissible;
    }
  }
  report::ResultFile orbit(c.dir, "fig16_orbit.csv");
  WriteTrajectoryHeader(orbit.stream(), c);
  const Eigen::MatrixXd orbit_tr = OrbitTrajectory(c.b, pick.start, kSamples);
  WriteTrajectory(orbit.stream(), "x", pick.start.period, orbit_tr);
  // (The right panel's x_c range: ContactTimeRange of the orbit's.)
  const std::string x_range = ContactTimeRange(c, orbit_tr.col(1 + c.contact).minCoeff(),
                                               orbit_tr.col(1 + c.contact).maxCoeff());
  // The energy axis (log) from just below the lowest drawn orbit (3-ipp or
  // 1-ipp in the window) to above the family's highest, not admissible ones
  // included (the continuation the caption follows), at most 20 times the
  // lowest: the admissible stretch fills the frame, the continuation's
  // spikes leave it at the top.
  double e_hi = 0.0, e_lo = INFINITY;
  for (const Orbit& o : pick.family) {
    if (o.period < t_lo || o.period > t_hi) continue;
    e_hi = std::max(e_hi, o.energy);
    e_lo = std::min(e_lo, o.energy);
  }
  for (const auto& list : c.atlas.one.at) {
    const Orbit& o = list.front().orbit;
    if (o.admissible && o.period >= t_lo && o.period <= t_hi) e_lo = std::min(e_lo, o.energy);
  }
  const bool found = std::isfinite(e_lo) && e_lo < e_hi;
  if (!found) e_lo = 1e-3 * e_hi;
  // (Without an orbit in the window to scale by, up to the family's highest.)
  const double bottom = 0.7 * e_lo, top = found ? std::min(1.5 * e_hi, 20.0 * e_lo) : 1.5 * e_hi;
  std::ostringstream body;
  // Two panels above one key for both (a key under each ran into the other
  // panel at the column's width); the energy axis from 0.7 of the lowest
  // orbit drawn, so that the lowest stretch and its label clear the frame.
  // The panels' foot, over the key's band (five rows at a column's width,
  // spaced for T_G's subscript; fewer where more columns fit: KeyFoot) and
  // the axes' labels.
  const std::string kFoot = KeyFoot(0.16, 0.18);
  body << "set multiplot\nset tmargin at screen 0.97\nset bmargin at screen " << kFoot << "\n"
       << "set lmargin at screen 0.12\nset rmargin at screen 0.53\n"
       << "set xlabel 'period T (s)'\nset ylabel 'energy E (J)'\nset logscale y\n" << LogTics("y", bottom, top)
       << "set xtics " << NiceStep(t_lo, t_hi, 5) << "\n"
       << "set xrange [" << t_lo << ":" << t_hi << "]\nset yrange [" << bottom << ":" << top << "]\n"
       << VerticalLines("ends", {pick.admissible_from, pick.admissible_to}, bottom, top);
  if (three[2] > 0) {
    // Under the stretch, at the family's lowest (above it are the grazing
    // circle and the 1-ipp branch).
    body << "set label 'stable' at " << s_t / three[2] << ", " << s_e / three[2] << " center offset 0, -1.1 front\n";
  }
  Plot energies("plot", Plot::Keys::kCollected);
  // (The continuation that is not admissible under the 1-ipp branch it
  // runs along past T_G.)
  energies.Add("'fig16_three_impact_family.csv' using 1:($5 == 0 ? $4 : 1/0)", With("not_admissible"),
               "3-ipp, not admissible", three[0])
      // (Markers along it: a short unstable stretch's dashes read as a
      // solid line.)
      .Add("'' using 1:($5 == 1 && $6 == 0 ? $4 : 1/0)", MarkersAlong("three_unstable", three[1]), "3-ipp, unstable",
           three[1])
      // (A dot on every stable orbit: the stretch may be two orbits long.)
      .Add("'' using 1:($5 == 1 && $6 == 1 ? $4 : 1/0)", With("three_stable", "linespoints"), "3-ipp, stable", three[2])
      // (The admissible 1-ipp branch over a white halo: past T_G the 3-ipp
      // continuation runs along it, and its dots between the 1-ipp dashes
      // read as the dash-dot of the dilated 2-ipp.)
      .Unkeyed("'fig16_one_impact.csv' using 1:($3 == 1 ? $2 : 1/0)", With("halo"))
      .Add("'' using 1:($3 == 1 && $4 == 1 ? $2 : 1/0)", With("one_stable"), "1-ipp, stable", one_stable)
      .Add("'' using 1:($3 == 1 && $4 == 0 ? $2 : 1/0)", With("one_unstable"), "1-ipp, unstable", one_unstable)
      .Add("$ends using 1:2", With("range_end"), "ends of admissibility");
  // The orbit drawn on the right is marked on its branch, and its stability named.
  const bool start_stable = OrbitStability(c.b, pick.start).stable;
  Mark(energies, pick.start.period, pick.start.energy, "picked",
       std::string("orbit at right, ") + (start_stable ? "stable" : "unstable"));
  // Where the family ends on the 1-ipp branch: its grazing orbit at T_G.
  const Orbit graze = OneImpactOrbit(c.b, pick.admissible_to);
  Mark(energies, graze.period, graze.energy, "grazing", "grazing orbit at T_G");
  // The right panel's impacts: t = 0 (and T), t2, t3.
  std::ostringstream impacts;
  impacts << "$impacts << EOD\n0," << c.b.gap << "\n";
  for (const double t : pick.start.times) impacts << t << "," << c.b.gap << "\n";
  impacts << pick.start.period << "," << c.b.gap << "\nEOD\n";
  Plot orbit_plot("plot", Plot::Keys::kCollected);
  // (The orbit unkeyed, solid and black, as the time history draws x_c:
  // the panel's axis names it, the left panel's diamond and its key say
  // where it is and its stability; dashed, its details were lost, and in
  // the family's purple it read as the key's "3-ipp, stable".)
  orbit_plot.Unkeyed("'fig16_orbit.csv' using " + std::to_string(TCol()) + ":" + std::to_string(XCol(c, c.contact)),
                     With("dof_contact"))
      .Add(std::to_string(c.b.gap), With("obstacle"), "obstacle d")
      .Add("$impacts using 1:2", With("orbit_impact"), "impacts (t = 0 again at T)");
  std::vector<Plot::Entry> entries = energies.Collected();
  entries.insert(entries.end(), orbit_plot.Collected().begin(), orbit_plot.Collected().end());
  // The stable stretch zoomed on where it is under 1 % of the period axis
  // (2 px: one dot beside its label), in the frame's freest place: what
  // the left panel draws marked (its orbits, the ends' lines, its marks).
  std::vector<Zoom> zooms;
  Occupancy free(t_lo, t_hi, bottom, top);
  if (three[2] > 0 && s_last - s_first < 0.01 * (t_hi - t_lo)) {
    for (const Orbit& o : pick.family) free.Mark(free.X(o.period), free.Y(o.energy));
    for (const auto& list : c.atlas.one.at) {
      const Orbit& o = list.front().orbit;
      if (o.admissible) free.Mark(free.X(o.period), free.Y(o.energy));
    }
    // (The ends' lines with 3 % of the frame each side: at their own width,
    // the inset's edge, its "28.86" and its leader ran within 10 px of the
    // T_G line in the column PDF.)
    for (const double t : {pick.admissible_from, pick.admissible_to}) {
      free.MarkBox(free.X(t) - 0.03, 0.0, free.X(t) + 0.03, 1.0);
    }
    for (const Orbit* o : {&pick.start, &graze}) {
      free.MarkBox(free.X(o->period) - 0.03, free.Y(o->energy) - 0.03, free.X(o->period) + 0.03, free.Y(o->energy) + 0.03);
    }
    const auto [w_lo, w_hi] = StretchWindow(s_first, s_last, t_hi - t_lo);
    const double mid = 0.5 * (w_lo + w_hi);
    const auto [e_lo, e_hi] = EnergySpan(pick.family, w_lo, w_hi);
    const double pad = 0.3 * (e_hi - e_lo);
    free.MarkBox(free.X(mid) - 0.1, free.Y(s_e / three[2]) - 0.08, free.X(mid) + 0.1, free.Y(s_e / three[2]));  // its label
    // (Most of the width between the ends' lines: its tick labels, five digits
    // of E, would fill a smaller one; one tick on T, two met in the column.)
    if (e_hi > e_lo) zooms.push_back({w_lo, w_hi, e_lo - pad, e_hi + pad, "", 0.62, 0.34, true});
  }
  body << ZoomInsets(free, energies, zooms, true) << impacts.str();
  // The right panel: what the left one (and its inset) set, reset.
  body << "set lmargin at screen 0.68\nset rmargin at screen 0.98\nset tmargin at screen 0.97\nset bmargin at screen "
       << kFoot << "\nunset object\nunset arrow\nset tics scale default\nset format y '% h'\n"
       << "unset logscale y\nunset label\nset xtics autofreq\nset ytics autofreq right offset 0, 0\nset mytics default\n" << x_range
       << "set xrange [0:" << pick.start.period << "]\n"
       << "set xlabel 'time t (s)'\nset ylabel '" << XcLabel(c) << "'\n" << orbit_plot.str() << LegendPanel(0.18)
       // (Spaced for the subscript of T_G, which touched the next row in the
       // column PDF.)
       << "set key spacing 1.2\n" << Plot::Legend(entries) << "unset multiplot";
  out.Commit();
  one.Commit();
  orbit.Commit();
  std::ostringstream note;
  note << "admissible for T in [" << std::setprecision(9) << pick.admissible_from << ", " << pick.admissible_to
       << "], the orbit drawn at T = " << pick.start.period;
  Draw(c, "fig16_three_impact_family", body.str(), note.str());
}

namespace {

// A contact as written (Contact::Describe: "x2 <= 1") as gnuplot's enhanced
// text: subscripted dofs, the relations as symbols.
std::string GnuplotText(const std::string& text) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text.compare(i, 2, "<=") == 0) {
      out += "{/Symbol \\243}";
      ++i;
    } else if (text.compare(i, 2, ">=") == 0) {
      out += "{/Symbol \\263}";
      ++i;
    } else if (text[i] == 'x' && i + 1 < text.size() && std::isdigit(static_cast<unsigned char>(text[i + 1]))) {
      out += "x_{";
      while (i + 1 < text.size() && std::isdigit(static_cast<unsigned char>(text[i + 1]))) out += text[++i];
      out += "}";
    } else {
      out += text[i];
    }
  }
  return out;
}

}  // namespace

// Fig. 18 (several contacts, issue 24): the frequency-energy plot of every
// family of one and two impacts per period, one colour per impact sequence:
// (j) for each contact, (j, j) and (j, k), j < k ((k, j) is (j, k) shifted
// by t2). Admissible orbits only, over the atlas's grid; 1-impact families
// as lines (solid stable, dashed unstable), 2-impact ones as branches
// (TwoImpactBranches) marked every few points (filled stable, open unstable). With a rigid-body mode (a free mass in a cavity)
// only the pairs (j, k), j < k, that can send the free motion back
// (two_impact.h CheckTwoImpactSequence).
void Figure18(Context& c) {
  const int k = static_cast<int>(c.b.contacts.size());
  if (k < 2) return;
  std::vector<std::vector<int>> sequences;
  if (c.b.rigid == 0) {
    for (int j = 0; j < k; ++j) sequences.push_back({j});
  }
  for (int j = 0; j < k; ++j) {
    for (int l = c.b.rigid == 0 ? j : j + 1; l < k; ++l) {
      try {
        CheckTwoImpactSequence(c.b, j, l);
        sequences.push_back({j, l});
      } catch (const InputError&) {
        // (no orbit of that pair: not drawn)
      }
    }
  }
  if (sequences.empty()) {
    c.log << "  fig18_sequences_fep: no pair of contacts has orbits with this rigid-body mode: not drawn\n";
    return;
  }
  report::ResultFile out(c.dir, "fig18_sequences_fep.csv");
  std::ostream& os = out.stream();
  os << "sequence,index,T,t2,energy,stable,branch,mark\n";
  std::vector<std::string> labels, titles;
  SweepOptions opt;
  opt.stability = StabilityPolicy::kAdmissible;
  double lo = INFINITY, hi = -INFINITY;
  std::vector<std::array<long, 2>> counts(sequences.size(), {0, 0});  // unstable, stable
  std::vector<double> energies;
  bool first = true;
  for (std::size_t s = 0; s < sequences.size(); ++s) {
    const std::vector<int>& seq = sequences[s];
    // (A stream: GCC 12 warns falsely (-Wrestrict) on chains of string + literal.)
    std::ostringstream label, title;
    title << "(";
    for (std::size_t i = 0; i < seq.size(); ++i) {
      label << (i ? "-" : "") << seq[i] + 1;
      title << (i ? ", " : "") << seq[i] + 1;
    }
    title << ")";
    // A one-impact sequence names its wall (the model's contact as written).
    if (seq.size() == 1 && c.model) title << " " << GnuplotText(c.model->contacts[static_cast<std::size_t>(seq[0])].Describe());
    labels.push_back(label.str());
    titles.push_back(title.str());
    opt.sequence = seq;
    // The admissible orbits of the sequence at each period of the grid,
    // joined into branches (a 1-impact family has one orbit per period: its
    // branches are its runs of consecutive periods).
    std::vector<FepTable::Root> roots;
    for (std::size_t i = 0; i < c.periods.size(); ++i) {
      for (const OrbitRecord& r : OrbitsAt(c.b, c.periods[i], static_cast<int>(seq.size()), opt)) {
        if (!r.orbit.admissible) continue;
        roots.push_back({static_cast<int>(i), r.orbit.period, seq.size() == 1 ? 0.0 : r.orbit.times[0], r.orbit.energy,
                         IsStable(r.stability)});
        counts[s][IsStable(r.stability)] += 1;
        energies.push_back(r.orbit.energy);
        lo = std::min(lo, r.orbit.energy);
        hi = std::max(hi, r.orbit.energy);
      }
    }
    std::vector<std::vector<FepTable::Root>> branches;
    if (seq.size() == 2) {
      branches = TwoImpactBranches(std::move(roots));
    } else {
      for (const FepTable::Root& r : roots) {
        if (branches.empty() || r.step != branches.back().back().step + 1) branches.emplace_back();
        branches.back().push_back(r);
      }
    }
    // A 2-impact sequence's markers at equal steps along its branches.
    const std::vector<std::vector<bool>> marks = EqualStepMarks(branches, true);
    for (std::size_t b = 0; b < branches.size(); ++b) {
      // (One blank line between branches: gnuplot breaks the line there.)
      os << (first ? "" : "\n");
      first = false;
      for (std::size_t i = 0; i < branches[b].size(); ++i) {
        const FepTable::Root& r = branches[b][i];
        os << labels.back() << "," << s << "," << r.period << "," << r.t2 << "," << r.energy << "," << r.stable << ","
           << b + 1 << "," << (seq.size() == 2 && marks[b][i]) << "\n";
      }
    }
  }
  out.Commit();
  if (!(lo < hi)) {
    c.log << "  fig18_sequences_fep: no admissible orbit of any sequence on the grid: not drawn\n";
    return;
  }
  std::ostringstream body;
  // Up to 30 times the median energy, as the other frequency-energy plots:
  // the families fill the frame, their diverging ends leave it.
  // Its top rounded up to a value the log axis labels, so that the top is
  // named: its ends labelled, 18.9 and 0.247 broke the set's rule of round
  // log labels and dropped 0.3; unlabelled, a reader asked what the top was.
  const double top = LogLabelledTop(0.8 * lo, std::min(2.0 * hi, EnergyTop(energies)));
  body << "set logscale y\n" << LogTics("y", 0.8 * lo, top) << "set yrange [" << 0.8 * lo << ":" << top << "]\n"
       << "set xlabel 'period T (s)'\nset ylabel 'energy E (J)'\nset xrange [0:" << PeriodTop(c) << "]\n"
       << "set key below";
  // The key's title names the walls the sequences number (a (1, 2) did not
  // say which wall was 2).
  // (A blank line over it: under the x label, it read as a second one.)
  if (c.model) {
    body << " title \"\\n\".'impacts per period, in order, on walls";
    for (std::size_t k = 0; k < c.model->contacts.size(); ++k) {
      body << (k ? ", " : " ") << k + 1 << ": " << GnuplotText(c.model->contacts[k].Describe());
    }
    body << "'";
  }
  body << "\n";
  // The 1-impact sequences as Fig. 8's 1-ipp family (solid and dashed lines,
  // no markers: the first in its blue and sky, the others in the sequences'
  // colours), over the 2-impact ones (where a 1-impact family runs along a
  // 2-impact branch, it showed under its markers; a white halo left crumbs
  // of the branches beside it); each
  // 2-impact sequence a line with markers at equal steps, in a role of its
  // own (Fig. 8's 2-ipp vermillion dots and orange circles first, then
  // purple squares, grey triangles): filled stable, open unstable, told
  // apart in greyscale by their shapes. The key first, sequence by sequence.
  Plot plot;
  std::vector<std::size_t> order;
  for (std::size_t s = 0; s < sequences.size(); ++s) {
    if (sequences[s].size() == 1) order.push_back(s);
  }
  for (std::size_t s = 0; s < sequences.size(); ++s) {
    if (sequences[s].size() == 2) order.push_back(s);
  }
  const std::pair<const char*, const char*> two_roles[] = {
      {"two_stable", "two_unstable"}, {"sequence_b_stable", "sequence_b_unstable"},
      {"sequence_c_stable", "sequence_c_unstable"}};
  struct Layer {
    std::string rows, look;
    bool one;
    const char* role;
    std::string colour;  // ("": the role's)
  };
  std::vector<Layer> layers;
  // The key's entries a row per sequence, stable then unstable, where each
  // sequence has both (gnuplot fills the key's columns first: the stable
  // entries, then the unstable ones, in columns as high as the sequences
  // are many); else in the sequences' order.
  // (A sequence with no admissible orbit has no entry.)
  const bool paired = std::all_of(order.begin(), order.end(), [&](std::size_t s) {
    return (counts[s][0] > 0) == (counts[s][1] > 0);
  });
  const long keyed = std::count_if(order.begin(), order.end(), [&](std::size_t s) { return counts[s][1] > 0; });
  std::vector<std::pair<std::string, std::string>> keys[2];  // unstable, stable
  std::size_t ones = 0, twos = 0;
  for (const std::size_t s : order) {
    const bool one = sequences[s].size() == 1;
    const std::size_t k = one ? ones++ : twos++;
    // Past the roles: the first ones again, coloured from the sequences' cycle.
    const std::string colour = one ? (k == 0 ? "" : style::CycleColour("sequences", k + 1))
                                   : (k < 3 ? "" : style::CycleColour("sequences", k));
    for (int stable : {1, 0}) {
      if (counts[s][stable] == 0) continue;
      const std::string rows = "strcol(1) eq '" + labels[s] + "' && $6 == " + std::to_string(stable);
      const char* role = one ? (stable ? "one_stable" : "one_unstable") : stable ? two_roles[k % 3].first
                                                                                 : two_roles[k % 3].second;
      const std::string look = With(role, one ? "lines" : "linespoints", colour);
      keys[paired ? stable : 1].push_back({look, titles[s] + (stable ? " stable" : " unstable")});
      layers.push_back({rows, one ? look : colour, one, role, colour});
    }
  }
  if (paired && keyed > 0) body << "set key maxrows " << keyed << " maxcols 2\n";
  for (const int stable : {1, 0}) {
    for (const auto& [look, title] : keys[stable]) plot.KeyOnly(look, title);
  }
  for (const Layer& l : layers) {
    if (!l.one) MarkedLine(plot, "'fig18_sequences_fep.csv'", "3", l.rows, "$5", 8, l.role, l.look);
  }
  // (An unstable one over its path drawn thin, as Fig. 8's: where the (1)
  // and (1, 1) dashes lay on each other, at T = 29.4-29.7, they read as one
  // two-coloured dash.)
  for (const Layer& l : layers) {
    if (!l.one) continue;
    const std::string using_rows = "'fig18_sequences_fep.csv' using 3:(" + l.rows + " ? $5 : 1/0)";
    if (std::string_view(l.role) == "one_unstable") plot.Unkeyed(using_rows, With("one_unstable_trace", "lines", l.colour));
    plot.Unkeyed(using_rows, l.look);
  }
  body << plot.str();
  Draw(c, "fig18_sequences_fep", body.str(), std::to_string(sequences.size()) + " impact sequences");
}

FiguresResult DrawPaperFigures(const Model& model, const AnalysisBasis& b, int contact, const Atlas& atlas,
                               const OutputDir& dir, std::ostream& log) {
  Context c{.b = b,
            .contact = contact,
            .other = contact == 0 ? (b.n > 1 ? 1 : 0) : 0,
            .dir = dir,
            .atlas = atlas,
            .log = log,
            .model = &model};
  c.log << "figures in " << c.dir.path().string() << ":\n";
  const ModalPick modal = PickModalTransition(c.b, c.atlas);
  Figure2(c);
  Figure3(c);
  Figure4(c, modal);
  Figure5(c);
  Figure6(c);
  Figure7(c);
  Figure8(c);
  Figure9(c);
  Figure10(c, modal);
  Figures11And12(c);
  Figures13To15(c);
  const ThreeImpactPick three = ThreeImpactFamilyExample(c.b, c.atlas);
  Figure16(c, three);
  Figure17(c);
  Figure18(c);
  // The pictures the dynamics needs, beside the paper's.
  FigureModel(c);
  FigureMultipliers(c);
  FigureTimeHistory(c);
  FigureValidation(c, three);
  FigureAllFamilies(c, three);
  c.log << c.drawn << " figures drawn" << (c.failed ? ", " + std::to_string(c.failed) + " failed" : "") << "\n";
  return {c.drawn, c.failed};
}

FiguresResult DrawSequenceFigures(const AnalysisBasis& b, const std::vector<double>& periods, const OutputDir& dir,
                                  std::ostream& log) {
  const Atlas none;
  Context c{.b = b, .contact = 0, .other = 0, .dir = dir, .atlas = none, .log = log, .periods = periods};
  c.log << "figures in " << c.dir.path().string() << ":\n";
  Figure18(c);
  c.log << c.drawn << " figures drawn" << (c.failed ? ", " + std::to_string(c.failed) + " failed" : "") << "\n";
  return {c.drawn, c.failed};
}

int DrawWorkPrecisionCharts(const OutputDir& dir, const std::vector<WorkPrecisionRow>& rows, std::ostream& log) {
  // A zero error (a run that reproduces the reference to the last bit) has
  // no place on a log scale: it is drawn at a floor a decade below the
  // smallest nonzero error of the case, open and labelled. A run whose impact
  // count is not the reference's is crossed out, whatever its error.
  std::vector<std::string> case_names, integrators;
  for (const WorkPrecisionRow& r : rows) {
    if (std::find(case_names.begin(), case_names.end(), r.case_name) == case_names.end()) {
      case_names.push_back(r.case_name);
    }
    if (std::find(integrators.begin(), integrators.end(), r.integrator) == integrators.end()) {
      integrators.push_back(r.integrator);
    }
  }
  int failed = 0;
  for (const std::string& name : case_names) {
    double smallest = std::numeric_limits<double>::infinity();
    for (const WorkPrecisionRow& r : rows) {
      if (r.case_name == name && r.error > 0.0 && std::isfinite(r.error)) smallest = std::min(smallest, r.error);
    }
    const double floor = std::isfinite(smallest) ? 0.1 * smallest : 1e-16;
    std::ostringstream body;
    // work_precision.csv: case 1, integrator 2, setting 3, error 4, cpu_s 5,
    // impacts 6, steps 7, expected_impacts 8. Each integrator in its own
    // style (style.toml: the same in every chart).
    body << "set datafile separator ','\nset logscale xy\nset format y '10^{%T}'\nset format x '10^{%T}'\n"
         << "set xlabel 'CPU time per run (s)'\nset ylabel 'relative error of the final state (vs exact, root\\_tol 1e-14)'\n"
         << "set key below\n"
         << "floor = " << floor << "\n"
         << "set arrow from graph 0, first floor to graph 1, first floor nohead " << style::Look("floor") << "\n"
         << "set label 'error 0 (drawn at this floor)' at graph 0.02, first floor offset 0, 0.7\n";
    Plot plot;
    long wrong = 0;
    bool zeno = false;
    for (const std::string& integrator : integrators) {
      long drawn = 0;
      for (const WorkPrecisionRow& r : rows) {
        if (r.case_name != name || r.integrator != integrator) continue;
        drawn += r.error > 0.0;
        wrong += r.impacts != r.expected_impacts;
        zeno = zeno || r.zeno;
      }
      const std::string select = "(strcol(1) eq '" + name + "' && strcol(2) eq '" + integrator + "'";
      plot.Add("'work_precision.csv' using " + select + " && $4 > 0 ? $5 : 1/0):4", With(integrator), integrator, drawn);
      plot.Unkeyed("'work_precision.csv' using " + select + " && $4 == 0 ? $5 : 1/0):(floor)", With(integrator, "points"));
    }
    // A Zeno case's impact count depends on where the accumulation is
    // truncated: not a check of the run (the caption says so).
    if (!zeno) {
      plot.Add("'work_precision.csv' using (strcol(1) eq '" + name + "' && $6 != $8 ? $5 : 1/0):($4 > 0 ? $4 : floor)",
               With("wrong_count"), "wrong impact count", wrong);
    }
    body << plot.str();
    const ChartStatus chart = DrawChart(dir, "work_precision_" + name, body.str());
    if (!chart.drawn) {
      log << "work_precision_" << name << " not drawn: " << chart.message << "\n";
      ++failed;
    }
  }
  return failed;
}

namespace {

// A grazing and a zero-velocity impact bound an admissible stretch of a
// response: the charts draw them whichever side of it they were computed on
// (at a zero velocity, a round-off of -1e-16 makes the orbit "not
// admissible"), the other special points where admissible.
bool BoundsAStretch(SpecialKind kind) { return kind == SpecialKind::kGrazing || kind == SpecialKind::kZeroVelocity; }
bool DrawnSpecialPoint(const SpecialPoint& p) { return p.orbit.admissible || BoundsAStretch(p.kind); }

// The response chart's plot with an inset on each group of three or more
// special points closer than their markers (3.5 % of the frame apart on
// both axes: a peak between two grazings and two period doublings within
// 0.02 rad/s piled up), or of two on each other, the two largest groups, each where the frame is
// free of the responses, the backbone and the points. `frame`: x from, to,
// y from, to (y logarithmic on the energy's chart, column 5).
std::string ResponseInsets(const std::vector<ResponseRow>& rows, const std::vector<SpecialPoint>& points,
                           const std::vector<OrbitRecord>* backbone, bool frequency, int periods, int col,
                           const std::array<double, 4>& frame, const Plot& plot) {
  const bool log_y = col == 5;
  Occupancy free(frame[0], frame[1], frame[2], frame[3], log_y);
  auto x_of = [frequency](const ForcedOrbit& o) { return frequency ? o.frequency : o.amplitude; };
  // (What the chart draws of an orbit: its energy, or its impact velocity
  // where it has impacts and the velocity is not below the axis.)
  auto y_of = [col](const ForcedOrbit& o) {
    if (col == 5) return o.energy > 0.0 ? o.energy : std::numeric_limits<double>::quiet_NaN();
    return o.impacts > 0 && o.min_impact_velocity >= -1e-12 ? o.min_impact_velocity
                                                            : std::numeric_limits<double>::quiet_NaN();
  };
  // The responses as drawn, each segment between two rows of a branch too.
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const double x = x_of(rows[k].orbit), y = y_of(rows[k].orbit);
    free.Mark(free.X(x), free.Y(y));
    if (k + 1 < rows.size() && rows[k + 1].branch == rows[k].branch) {
      free.MarkSegment(free.X(x), free.Y(y), free.X(x_of(rows[k + 1].orbit)), free.Y(y_of(rows[k + 1].orbit)), 8);
    }
  }
  if (backbone && log_y) {
    for (const OrbitRecord& r : *backbone) {
      if (r.orbit.admissible) free.Mark(free.X(periods * 2.0 * std::numbers::pi / r.orbit.period), free.Y(r.orbit.energy));
    }
  }
  // The special points drawn, as fractions of the frame.
  struct Drawn {
    double x, y, fx, fy;
    int group;
  };
  std::vector<Drawn> drawn;
  for (const SpecialPoint& p : points) {
    const double x = x_of(p.orbit), y = y_of(p.orbit);
    if (!DrawnSpecialPoint(p) || !std::isfinite(y) || x < frame[0] || x > frame[1]) continue;
    const double fx = free.X(x), fy = free.Y(y);
    if (fy < 0.0 || fy > 1.0) continue;
    free.MarkBox(fx - 0.015, fy - 0.015, fx + 0.015, fy + 0.015);
    drawn.push_back({x, y, fx, fy, static_cast<int>(drawn.size())});
  }
  // Groups: points joined when within 3.5 % on both axes (single linkage).
  for (bool merged = true; merged;) {
    merged = false;
    for (Drawn& a : drawn) {
      for (Drawn& b : drawn) {
        if (a.group != b.group && std::abs(a.fx - b.fx) < 0.035 && std::abs(a.fy - b.fy) < 0.035) {
          const int from = std::max(a.group, b.group), to = std::min(a.group, b.group);
          for (Drawn& d : drawn) d.group = d.group == from ? to : d.group;
          merged = true;
        }
      }
    }
  }
  std::map<int, std::vector<const Drawn*>> groups;
  for (const Drawn& d : drawn) groups[d.group].push_back(&d);
  std::vector<std::vector<const Drawn*>> piled;
  // (Three or more; two when their markers lie on each other, within 2 %
  // on both axes: the fold on the period doubling at w = 0.683.)
  for (auto& [g, members] : groups) {
    const bool on_each_other = members.size() == 2 && std::abs(members[0]->fx - members[1]->fx) < 0.02 &&
                               std::abs(members[0]->fy - members[1]->fy) < 0.02;
    if (members.size() >= 3 || on_each_other) piled.push_back(members);
  }
  std::stable_sort(piled.begin(), piled.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
  if (piled.size() > 2) piled.resize(2);
  std::vector<Zoom> zooms;
  for (const auto& members : piled) {
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (const Drawn* d : members) {
      x0 = std::min(x0, d->x);
      x1 = std::max(x1, d->x);
      y0 = std::min(y0, d->y);
      y1 = std::max(y1, d->y);
    }
    // The group in the inset's middle half, at least 3.5 % of the frame wide
    // (2 % on the energy chart) and 8 % high: the markers clear of each other at the inset's scale,
    // and the window's box on the chart about their size (at 2 % by 6 %, the
    // amplitude chart's box at 0.683 was 12 px wide in the column PDF, its
    // markers over its sides).
    // (The energy chart's window 2 % wide: at 3.5 %, its grazing circle and
    // peak diamond met in the inset.)
    const double px = std::max(0.5 * (x1 - x0), (log_y ? 0.01 : 0.0175) * (frame[1] - frame[0]));
    const double py = log_y ? std::max(0.5 * (y1 - y0), 0.06 * y1) : std::max(0.5 * (y1 - y0), 0.04 * (frame[3] - frame[2]));
    // (The energy chart's 0.40 by 0.25 of the frame: at 0.34 by 0.32,
    // taller than the free band above its curves, it was drawn at 0.65 of
    // that, about 1 by 0.7 cm in the column PDF; on the amplitude chart, so
    // flat, its markers met.)
    zooms.push_back({x0 - px, x1 + px, std::max(y0 - py, log_y ? 0.5 * y0 : frame[2]), y1 + py, "",
                     log_y ? 0.40 : 0.34, log_y ? 0.25 : 0.32});
  }
  return ZoomInsets(free, plot, zooms, false);
}

}  // namespace

int DrawResponseCharts(const OutputDir& dir, const std::vector<ResponseRow>& rows,
                       const std::vector<SpecialPoint>& points, int dofs, const std::vector<OrbitRecord>* backbone,
                       bool frequency, int periods, std::ostream& log) {
  double e_min = std::numeric_limits<double>::infinity(), e_max = 0.0, v_max = 0.0;
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo;
  // The levels of the held parameter (the amplitude beside a frequency grid),
  // in order, and the branches of each with their counts of admissible
  // stable and unstable orbits.
  std::vector<double> levels;
  std::map<int, std::size_t> level_of;
  for (const ResponseRow& r : rows) {
    if (r.orbit.energy > 0.0) e_min = std::min(e_min, r.orbit.energy);
    e_max = std::max(e_max, r.orbit.energy);
    if (r.orbit.impacts > 0 && r.orbit.admissible) v_max = std::max(v_max, r.orbit.min_impact_velocity);
    // The frame holds the admissible responses (a branch admissible nowhere
    // is drawn where it meets them, not followed across an empty axis).
    const double x = frequency ? r.orbit.frequency : r.orbit.amplitude;
    if (r.orbit.admissible) {
      x_lo = std::min(x_lo, x);
      x_hi = std::max(x_hi, x);
    }
    const double held = frequency ? r.orbit.amplitude : r.orbit.frequency;
    if (std::find(levels.begin(), levels.end(), held) == levels.end()) levels.push_back(held);
    level_of[r.branch] = static_cast<std::size_t>(std::find(levels.begin(), levels.end(), held) - levels.begin());
  }
  if (rows.empty() || !(e_max > 0.0)) return 0;
  if (!(x_hi >= x_lo)) {  // nothing admissible: the whole sweep
    for (const ResponseRow& r : rows) {
      x_lo = std::min(x_lo, frequency ? r.orbit.frequency : r.orbit.amplitude);
      x_hi = std::max(x_hi, frequency ? r.orbit.frequency : r.orbit.amplitude);
    }
  }
  // The special points (located between grid points) inside the frame too.
  for (const SpecialPoint& p : points) {
    if (!p.orbit.admissible) continue;
    const double x = frequency ? p.orbit.frequency : p.orbit.amplitude;
    x_lo = std::min(x_lo, x);
    x_hi = std::max(x_hi, x);
    if (p.orbit.energy > 0.0) e_min = std::min(e_min, p.orbit.energy);
    e_max = std::max(e_max, p.orbit.energy);
    if (p.orbit.impacts > 0) v_max = std::max(v_max, p.orbit.min_impact_velocity);
  }
  // response.csv columns (1-based, tables.h): w 1, amplitude 2, energy 5,
  // max_xc 6, impact_velocity 7, admissible 8, stable 9, branch 12 + 2N.
  const std::string branch_col = std::to_string(12 + 2 * dofs), x = frequency ? "1" : "2";
  const double frame_lo = x_lo - 0.05 * (x_hi - x_lo), frame_hi = x_hi + 0.05 * (x_hi - x_lo);
  int failed = 0;
  for (const auto& [name, col, label] :
       {std::tuple<std::string, int, std::string>{"response_energy", 5, "mean energy (J)"},
        {"response_amplitude", 7, "velocity before impact v_c (m/s)"}}) {
    std::ostringstream body;
    // (Five rows a column at most: at a journal's column width gnuplot set
    // the 13 entries in one column, 45 % of the height.)
    body << std::setprecision(17) << "set datafile separator ','\nset key below maxrows 5\n"
         << "set xlabel '" << (frequency ? "forcing frequency {/Symbol w} (rad/s)" : "forcing amplitude a (N)") << "'\n"
         << "set ylabel '" << label << "'\n"
         << "set xrange [" << frame_lo << ":" << frame_hi << "]\n";
    // The responses fill the frame; the backbone leaves it where it diverges
    // (towards its singular transitions).
    // (The impact velocity's axis a little below 0: a zero-velocity impact,
    // located at -1e-16, is marked on the frame's foot, not cut.)
    const bool log_y = col == 5;
    const double top = v_max > 0.0 ? 1.3 * v_max : 1.0;
    const double y_lo = log_y ? 0.8 * e_min : -0.03 * top, y_hi = log_y ? 1.5 * e_max : top;
    if (log_y) body << "set logscale y\n" << LogTics("y", y_lo, y_hi);
    body << "set yrange [" << y_lo << ":" << y_hi << "]\n";
    // What each branch draws on this chart: an orbit without impact has no
    // impact velocity, one not admissible may have a negative one (below
    // the axis).
    std::map<int, std::array<long, 3>> count;  // branch -> not admissible, unstable, stable
    for (const ResponseRow& r : rows) {
      const double at = frequency ? r.orbit.frequency : r.orbit.amplitude;
      if (at >= frame_lo && at <= frame_hi &&
          (col == 7 ? r.orbit.impacts > 0 && r.orbit.min_impact_velocity >= 0.0 : r.orbit.energy > 0.0)) {
        ++count[r.branch][r.orbit.admissible ? 1 + r.orbit.stable : 0];
      }
    }
    // Each level in its colour, sampled on the level map (dark: the
    // lowest): stable solid, unstable dashed, not admissible dotted. Two
    // keys side by side (a level's three entries made a key of 15 that took
    // a third of a column's height): the levels by colour, each in the
    // first style it draws, then the styles in grey (where two levels or
    // more draw them; with one level, that level's own entries).
    Plot plot;
    const std::string y = std::to_string(col);
    const char* roles[] = {"response_not_admissible", "response_unstable", "response_stable"};  // count's index
    const char* names[] = {"not admissible", "unstable", "stable"};
    std::array<long, 3> styled{0, 0, 0};  // levels drawing each style
    std::array<std::pair<std::string, std::string>, 3> alone;  // a style one level draws: that level's entry (title, look)
    for (std::size_t k = 0; k < levels.size(); ++k) {
      const std::string colour = style::MapColour("level", levels.size() < 2 ? 0.0 : k / (levels.size() - 1.0));
      std::ostringstream level;
      level << (frequency ? "a = " : "{/Symbol w} = ") << levels[k] << (frequency ? " N" : " rad/s");
      bool keyed = false;
      for (int what : {2, 1, 0}) {  // stable, unstable, not admissible
        bool drawn = false;
        for (const auto& [branch, n] : count) {
          if (level_of[branch] != k || n[what] == 0) continue;
          const std::string spec = "'response.csv' using ($" + branch_col + " == " + std::to_string(branch) +
                                   (what == 0 ? " && $8 == 0" : " && $8 == 1 && $9 == " + std::to_string(what - 1)) +
                                   " ? $" + x + " : 1/0):" + y;
          const std::string look = With(roles[what], "lines", colour);
          if (levels.size() < 2 && !drawn) {
            plot.Add(spec, look, level.str() + ", " + names[what]);
          } else {
            plot.Unkeyed(spec, look);
          }
          if (levels.size() >= 2 && !keyed) plot.KeyOnly(look, level.str());
          drawn = keyed = true;
        }
        styled[what] += drawn;
        if (drawn) alone[what] = {level.str() + ", " + names[what], With(roles[what], "lines", colour)};
      }
    }
    if (levels.size() >= 2) {
      for (int what : {2, 1, 0}) {
        if (styled[what] >= 2) plot.KeyOnly(With(roles[what], "lines", style::Colour("grey")), names[what]);
        if (styled[what] == 1) plot.KeyOnly(alone[what].second, alone[what].first);
      }
    }
    if (backbone) {
      // backbone.csv: w 1, T 2, energy 3, admissible 4, stable 5, impact_velocity 7.
      const std::string by = col == 5 ? "3" : "7";
      long drawn[2] = {0, 0};  // unstable, stable admissible orbits of the backbone
      for (const OrbitRecord& r : *backbone) drawn[IsStable(r.stability)] += r.orbit.admissible;
      plot.Add("'backbone.csv' using ($4 == 1 && $5 == 1 ? " + std::to_string(periods) + " * $1 : 1/0):" + by,
               With("backbone"), "backbone, stable", drawn[1])
          .Add("'backbone.csv' using ($4 == 1 && $5 == 0 ? " + std::to_string(periods) + " * $1 : 1/0):" + by,
               With("backbone_unstable"), "backbone, unstable", drawn[0]);
    }
    // The special points of the admissible parts (response_points.csv: w 1,
    // amplitude 2, kind 3, energy 4, impact_velocity 7, admissible 8).
    const int pcol = col == 5 ? 4 : 7;
    for (const auto& [kind, role] : {std::pair<SpecialKind, const char*>{SpecialKind::kFold, "fold"},
                                     {SpecialKind::kPeriodDoubling, "multiplier_minus_one"},
                                     {SpecialKind::kGrazing, "grazing"},
                                     {SpecialKind::kZeroVelocity, "zero_velocity"},
                                     {SpecialKind::kPeak, "peak"},
                                     {SpecialKind::kTorus, "torus"}}) {
      const SpecialKind k = kind;  // (a structured binding cannot be captured before C++20's clang 16)
      const std::string name_of_kind = ToString(k);
      const long n = std::count_if(points.begin(), points.end(),
                                   [k](const SpecialPoint& p) { return p.kind == k && DrawnSpecialPoint(p); });
      plot.Add("'response_points.csv' using (strcol(3) eq '" + name_of_kind + "'" +
                   (BoundsAStretch(k) ? "" : " && $8 == 1") + " ? $" + x + " : 1/0):" + std::to_string(pcol),
               With(role), name_of_kind, n);
    }
    body << ResponseInsets(rows, points, backbone, frequency, periods, col, {frame_lo, frame_hi, y_lo, y_hi}, plot);
    const ChartStatus chart = DrawChart(dir, name, body.str());
    if (!chart.drawn) {
      log << name << " not drawn: " << chart.message << "\n";
      ++failed;
    }
  }
  return failed;
}

int DrawCurveChart(const OutputDir& dir, const std::vector<CurvePoint>& rows, int dofs, const std::string& followed,
                   const std::string& first, const std::string& second, const std::vector<Transition>* backbone,
                   int periods, std::ostream& log) {
  if (rows.empty()) return 0;
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo, y_lo = x_lo, y_hi = -x_lo;
  std::map<std::string, long> count;  // rows per kind
  for (const CurvePoint& p : rows) {
    x_lo = std::min(x_lo, p.first);
    x_hi = std::max(x_hi, p.first);
    y_lo = std::min(y_lo, p.second);
    y_hi = std::max(y_hi, p.second);
    ++count[p.kind];
  }
  const double dx = std::max(x_hi - x_lo, 1e-12 * std::abs(x_hi)), dy = std::max(y_hi - y_lo, 1e-12 * std::abs(y_hi));
  const double frame[4] = {x_lo - 0.03 * dx, x_hi + 0.03 * dx, y_lo - 0.03 * dy, y_hi + 0.03 * dy};
  std::ostringstream body;
  // (Names as gnuplot text: brackets and underscores escaped.)
  auto label = [](std::string name) {
    std::string out;
    for (char ch : name) out += ch == '_' || ch == '[' || ch == ']' ? std::string("\\") + ch : std::string(1, ch);
    return out;
  };
  body << std::setprecision(17) << "set datafile separator ','\nset key below\n"
       << "set xlabel '" << (first == "frequency" ? std::string("forcing frequency {/Symbol w} (rad/s)") : label(first))
       << "'\nset ylabel '" << (second == "amplitude" ? std::string("forcing amplitude a (N)") : label(second)) << "'\n"
       << "set xrange [" << frame[0] << ":" << frame[1] << "]\nset yrange [" << frame[2] << ":" << frame[3] << "]\n";
  Plot plot;
  if (backbone) {
    std::map<TransitionKind, std::vector<double>> at;
    for (const Transition& t : *backbone) {
      const double w = periods * 2.0 * M_PI / t.period;
      if (w >= frame[0] && w <= frame[1]) at[t.kind].push_back(w);
    }
    body << VerticalLines("backbone_singular", at[TransitionKind::kSingular], frame[2], frame[3])
         << VerticalLines("backbone_modal", at[TransitionKind::kModal], frame[2], frame[3]);
    plot.Add("$backbone_singular using 1:2", With("singular"), "backbone: singular transition",
             static_cast<long>(at[TransitionKind::kSingular].size()))
        .Add("$backbone_modal using 1:2", With("modal"), "backbone: linear modal transition",
             static_cast<long>(at[TransitionKind::kModal].size()));
  }
  // curve.csv (tables.h): first 1, second 2, kind 3, response.csv's w to
  // t_impact 4-14, the state 15 to 14 + 2N, curve 15 + 2N. One line per
  // curve, its rows in order along it.
  int curves = 0;
  for (const CurvePoint& p : rows) curves = std::max(curves, p.curve + 1);
  const std::string role = followed == "fold" ? "curve_fold" : followed == "grazing" ? "curve_grazing"
                                                                                     : "curve_period_doubling";
  const int curve_col = 15 + 2 * dofs;
  for (int c = 0; c < curves; ++c) {
    const std::string spec = "'curve.csv' using ($" + std::to_string(curve_col) + " == " + std::to_string(c + 1) +
                             " ? $1 : 1/0):2";
    if (c == 0) {
      plot.Add(spec, With(role), followed + " curve", count[followed]);
    } else {
      plot.Unkeyed(spec, With(role));
    }
  }
  for (const auto& [kind, marker] : {std::pair<const char*, const char*>{"fold", "fold"},
                                     {"period-doubling", "multiplier_minus_one"},
                                     {"grazing", "grazing"},
                                     {"zero-velocity", "zero_velocity"},
                                     {"cusp", "cusp"}}) {
    if (kind == followed) continue;
    plot.Add("'curve.csv' using (strcol(3) eq '" + std::string(kind) + "' ? $1 : 1/0):2", With(marker),
             std::string("meets ") + (std::string(kind) == "cusp" ? "itself: cusp" : kind), count[kind]);
  }
  body << plot.str();
  const ChartStatus chart = DrawChart(dir, "curve", body.str());
  if (!chart.drawn) {
    log << "curve not drawn: " << chart.message << "\n";
    return 1;
  }
  return 0;
}

}  // namespace nsmodal::report
