// nsmodal figures: the paper's Figs. 2-15 redrawn from the project's own
// computations. Each figure is DIR/figNN_name.{csv,png,svg} (+ the gnuplot
// scripts), the CSV holding exactly what is drawn. Trajectory CSVs hold one
// orbit per block, blocks separated by a blank line (gnuplot's convention for
// separate curves). Which orbits are drawn is chosen from the scene's own
// transitions, so another system gets the corresponding figures.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>

#include "nsmodal/figures.h"
#include "nsmodal/admissibility.h"
#include "nsmodal/atlas.h"
#include "nsmodal/figure_subjects.h"
#include "nsmodal/stability.h"
#include "nsmodal/bridge.h"
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

namespace nsmodal::report {
namespace {

// One visual language for every figure (Okabe-Ito, colour-blind safe), each
// colour with one meaning; stable is dark, unstable light (apart in greyscale
// too), and lines also change dash where it matters:
//   1-ipp blue (dark #0072B2 stable, sky #56B4E9 unstable); 2-ipp vermillion
//   (#D55E00 stable, orange #E69F00 unstable); 2-ipp with t2 = T/2 (the
//   dilated 1-ipp) bluish green; 3-ipp reddish purple; potential or not
//   admissible grey; the limits of a family (a grazing linear mode, a grazing
//   orbit) and the obstacle black. Continua (orbits along a branch) are
//   shaded with viridis and a colour bar.
constexpr const char* kOneStable = "#0072B2";
constexpr const char* kOneUnstable = "#56B4E9";
constexpr const char* kTwoStable = "#D55E00";
constexpr const char* kTwoUnstable = "#E69F00";
constexpr const char* kDilated = "#009E73";
constexpr const char* kThree = "#CC79A7";
constexpr const char* kPotential = "#BBBBBB";
constexpr const char* kNotAdmissible = "#777777";
constexpr const char* kViridis =
    "set palette defined (0 '#440154', 0.25 '#3B528B', 0.5 '#21908C', 0.75 '#5DC863', 1 '#FDE725')\n";
constexpr int kSamples = 200;  // per flight of a drawn trajectory

struct Context {
  const AnalysisBasis& b;
  int contact = 0;  // physical index of the contact dof
  int other = 0;    // the dof on the first axis of the phase sections (paper: x_1)
  const OutputDir& dir;
  const Atlas& atlas;
  std::ostream& log;
  const std::vector<double>& periods = atlas.one.periods;
  const std::vector<Transition>& transitions = atlas.transitions;
  const std::vector<Bridge>& bridges = atlas.bridges;
  int drawn = 0, failed = 0;
};

// Axis labels, in the paper's SI units (gnuplot enhanced text).
std::string DofLabel(const char* symbol, int dof, const char* unit) {
  return std::string(symbol) + "_{" + std::to_string(dof + 1) + "} (" + unit + ")";
}
std::string XcLabel(const Context& c) { return "contact displacement " + DofLabel("x", c.contact, "m"); }

// The data files must be closed (flushed) before this is called. Figures
// carry no titles (captions go with the figure, README "The paper's
// figures"): `note` is the caption's numbers, printed beside the name.
void Draw(Context& c, const std::string& name, const std::string& body, const std::string& note = "") {
  // Offsets keep a curve that touches d off the frame of an autoscaled axis.
  const std::string setup = "set datafile separator ','\nset grid\nset offsets graph 0, graph 0, graph 0.05, graph 0.05\n";
  const report::ChartStatus s = report::DrawChart(c.dir, name, setup + body);
  (s.drawn ? c.drawn : c.failed) += 1;
  c.log << "  " << name << (note.empty() ? "" : ": " + note) << (s.drawn ? "" : ": not drawn: " + s.message) << "\n";
}

bool IsStable(const std::optional<Stability>& s) { return s && s->stable; }


// Trajectory rows of one orbit: label, T, then OrbitTrajectory's columns.
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
                     long flight_rows = 0) {
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

// Columns of a trajectory CSV (1-based for gnuplot): t, x_i, v_i.
int TCol() { return 3; }
int XCol(const Context&, int dof) { return 4 + dof; }


// Energy range of a frequency-energy plot: from half the lowest potential
// energy up to 100 times the highest admissible one, at most four decades
// (energies diverge at singular transitions).
std::pair<double, double> EnergyRange(const Context& c) {
  double lo = INFINITY, hi = 0.0;
  for (const Sweep* sweep : {&c.atlas.one, &c.atlas.two}) {
    for (const auto& list : sweep->at) {
      for (const OrbitRecord& r : list) {
        if (r.orbit.potential) lo = std::min(lo, r.orbit.energy);
        if (r.orbit.admissible) hi = std::max(hi, r.orbit.energy);
      }
    }
  }
  if (!(hi > 0.0)) hi = 1.0;
  if (!std::isfinite(lo)) lo = 1e-3 * hi;
  return {0.5 * lo, std::min(100.0 * hi, 1e4 * lo)};
}

std::string EnergyAxes(const Context& c) {
  const auto [lo, hi] = EnergyRange(c);
  std::ostringstream os;
  os << "set logscale y\nset format y '10^{%T}'\nset yrange [" << lo << ":" << hi << "]\n"
     << "set xlabel 'period T (s)'\nset ylabel 'energy E (J)'\nset xrange [0:" << c.periods.back() << "]\n";
  return os.str();
}

// A chart of x_c(t) over one period of one orbit (Figs. 2, 5, 9) in `colour`:
// the orbit's samples to DIR/NAME.csv, the obstacle at d, the part of x_c
// above d filled (an NC3 failure is seen, not read off a number). `setup` is
// gnuplot set-up before the plot, `layers` more plot layers after it.
void DrawOneOrbit(Context& c, const std::string& name, const Orbit& o, const char* colour,
                  const std::string& setup, const std::string& layers, const std::string& note) {
  report::ResultFile out(c.dir, name + ".csv");
  WriteTrajectoryHeader(out.stream(), c);
  WriteTrajectory(out.stream(), "x", o.period, OrbitTrajectory(c.b, o, kSamples));
  out.Commit();
  const std::string xc = std::to_string(TCol()) + ":" + std::to_string(XCol(c, c.contact));
  std::ostringstream body;
  body << "set xlabel 'time t (s)'\nset ylabel '" << XcLabel(c) << "'\nset key below\nset xrange [0:" << o.period
       << "]\n"
       << setup << "plot '" << name << ".csv' using " << xc << " with filledcurves above y=" << c.b.gap
       << " fs solid 0.5 noborder lc rgb '" << kPotential << "' title 'x_c > d', "
       << "'' using " << xc << " with lines lw 2 lc rgb '" << colour << "' title 'x_c(t)', " << c.b.gap
       << " with lines dt 2 lc rgb 'black' title 'obstacle d'" << (layers.empty() ? "" : ", " + layers);
  Draw(c, name, body.str(), note);
}

// A plot layer circling the point (t, x); an empty title: no key entry.
std::string CircleMark(double t, double x, const std::string& title) {
  std::ostringstream os;
  os << "'+' using (" << t << "):(" << x << ") every ::0::0 with points pt 6 ps 2 lw 2 lc rgb 'black' "
     << (title.empty() ? "notitle" : "title '" + title + "'");
  return os.str();
}

// Plot layers circling the points (t, d) where an orbit grazes the obstacle.
std::string GrazeMarks(const Context& c, const std::vector<double>& times) {
  std::string layers;
  for (std::size_t k = 0; k < times.size(); ++k) {
    layers += (k ? ", " : "") + CircleMark(times[k], c.b.gap, k ? "" : "graze: x_c = d, v_c = 0");
  }
  return layers;
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
  setup << "set arrow from " << t2 << ", graph 0 to " << t2 << ", graph 1 nohead dt 3 lc rgb 'gray50'\n"
        << "set label 't_2' at " << t2 << ", graph 1 offset 0.5, -1\n";
  std::ostringstream note;
  note << "T = " << pick->period << ", t2 = " << t2 << ", x_c(t2) = " << x_t2 << ", x_c exceeds d by up to "
       << pick->max_excess;
  DrawOneOrbit(c, "fig02_not_admissible", *pick, kNotAdmissible, setup.str(),
               CircleMark(t2, x_t2, "x_c(t_2) {/Symbol \\271} d: NC2 fails"), note.str());
}

// Fig. 3: 1-ipp energies, admissible zones coloured by stability, transitions.
void Figure3(Context& c) {
  report::ResultFile out(c.dir, "fig03_one_impact.csv");
  out << "T,energy,potential,admissible,stable,max_multiplier\n";
  for (const auto& list : c.atlas.one.at) {
    const Orbit& o = list.front().orbit;
    const std::optional<Stability>& stability = list.front().stability;
    out << o.period << "," << o.energy << "," << o.potential << "," << o.admissible << ","
        << IsStable(stability) << ",";
    if (stability) out << stability->max_modulus;
    out << "\n";
  }
  report::ResultFile tr(c.dir, "fig03_transitions.csv");
  tr << "T,kind,energy\n";
  std::ostringstream arrows;
  for (const Transition& t : c.transitions) {
    tr << t.period << "," << ToString(t.kind) << "," << t.energy << "\n";
    if (t.kind == TransitionKind::kSingular || t.kind == TransitionKind::kModal) {
      arrows << "set arrow from " << t.period << ", graph 0 to " << t.period << ", graph 1 nohead lw 1 "
             << (t.kind == TransitionKind::kSingular ? "dt 2 lc rgb 'black'" : "dt 3 lc rgb '#777777'") << "\n";
    }
  }
  std::ostringstream body;
  body << EnergyAxes(c) << arrows.str() << "set key below\n"
       << "plot 'fig03_one_impact.csv' using 1:($3 == 1 ? $2 : 1/0) with lines lw 1 lc rgb '" << kPotential
       << "' title 'potential', "
       << "'' using 1:($4 == 1 && $5 == 1 ? $2 : 1/0) with lines lw 2.5 lc rgb '" << kOneStable
       << "' title 'admissible, stable', "
       << "'' using 1:($4 == 1 && $5 == 0 ? $2 : 1/0) with lines lw 1.5 dt 2 lc rgb '" << kOneUnstable << "'"
       << " title 'admissible, unstable', "
       << "'fig03_transitions.csv' using 1:(strcol(2) eq 'grazing' ? $3 : 1/0) with points pt 6 ps 1.5 lw 2 lc rgb "
          "'black' title 'grazing transition T_G', "
       << "'' using 1:(strcol(2) eq 'multiplier+1' ? $3 : 1/0) with points pt 8 ps 1.5 lw 2 lc rgb 'black' "
          "title 'multipliers through +1', "
       << "'' using 1:(strcol(2) eq 'multiplier-1' ? $3 : 1/0) with points pt 10 ps 1.5 lw 2 lc rgb 'black' "
          "title 'multipliers through -1 (period doubling)', "
       << "1/0 with lines dt 2 lc rgb 'black' title 'singular transition T_S', "
       << "1/0 with lines dt 3 lc rgb '#777777' title 'linear modal transition k T_i'";
  out.Commit();
  tr.Commit();
  Draw(c, "fig03_one_impact_energy", body.str());
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
  WriteTrajectory(out.stream(), "modal", mode.period, OrbitTrajectory(c.b, mode, kSamples));
  WriteTrajectory(out.stream(), "not_admissible", beyond.period, OrbitTrajectory(c.b, beyond, kSamples));
  std::ostringstream body;
  body << "set xlabel 'normalised time t / T'\nset ylabel '" << XcLabel(c) << "'\nset key below\n"
       << "plot 'fig04_modal_transition.csv' using (strcol(1) eq 'admissible' ? $3/$2 : 1/0):" << XCol(c, c.contact)
       << " with lines lw 2 lc rgb '" << kOneStable << "' title 'T = " << in.period << " (admissible)', "
       << "'' using (strcol(1) eq 'modal' ? $3/$2 : 1/0):" << XCol(c, c.contact)
       << " with lines lw 2 lc rgb 'black' title 'T = " << m.period << " (grazing linear mode)', "
       << "'' using (strcol(1) eq 'not_admissible' ? $3/$2 : 1/0):" << XCol(c, c.contact)
       << " with lines lw 2 dt 2 lc rgb '" << kNotAdmissible << "' title 'T = " << beyond.period
       << " (x_c > d: not admissible)', "
       << c.b.gap << " with lines dt 3 lc rgb 'black' title 'obstacle d'";
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
  DrawOneOrbit(c, "fig05_grazing_transition", OneImpactOrbit(c.b, br.period), kOneStable, "",
               GrazeMarks(c, {br.t2}), note.str());
}

// Fig. 6: det A_2(t2, T) against t2 for T = 1..10, with its roots.
void Figure6(Context& c) {
  report::ResultFile out(c.dir, "fig06_det_a2.csv");
  report::ResultFile roots(c.dir, "fig06_roots.csv");
  out << "T,t2,det\n";
  roots << "T,t2,half_period\n";
  for (int period = 1; period <= 10; ++period) {
    for (int j = 1; j < 1000; ++j) {
      const double t2 = period * j / 1000.0;
      out << period << "," << t2 << "," << MatrixA(c.b, {t2}, period).determinant() << "\n";
    }
    out << "\n";
    for (double r : TwoImpactRoots(c.b, period)) {
      roots << period << "," << r << "," << AtHalfPeriod(r, period) << "\n";
    }
  }
  std::ostringstream body;
  body << "set multiplot layout 2,5\n"
       << "unset key\nset xlabel 't_2 (s)'\nset ylabel 'det A_2'\n";
  for (int period = 1; period <= 10; ++period) {
    body << "set title 'T = " << period << "'\nset xrange [0:" << period << "]\nset xtics " << 0.5 * period
         << "\n"
         << "plot 'fig06_det_a2.csv' using ($1 == " << period << " ? $2 : 1/0):3 with lines lw 1.5 lc rgb '" << kOneStable << "', "
         << "'fig06_roots.csv' using ($1 == " << period << " && $3 == 1 ? $2 : 1/0):(0) with points pt 6 ps 1.0 lw 1.5 "
         << "lc rgb 'black', "
         << "'' using ($1 == " << period << " && $3 == 0 ? $2 : 1/0):(0) with points pt 7 ps 0.8 lc rgb '#D55E00'\n";
  }
  body << "unset multiplot";
  out.Commit();
  roots.Commit();
  Draw(c, "fig06_det_a2", body.str());
  // The roots as curves in the (t2, T) plane, from the atlas's 2-ipp sweep:
  // the trivial line t2 = T/2 (eq. 26) and the nontrivial curves, potential
  // and admissible apart.
  report::ResultFile curves(c.dir, "fig06_root_curves.csv");
  curves << "T,t2,half_period,admissible\n";
  for (const auto& list : c.atlas.two.at) {
    for (const OrbitRecord& r : list) {
      if (!r.orbit.potential) continue;
      curves << r.orbit.period << "," << r.orbit.times[0] << "," << IsHalfPeriodRoot(r.orbit) << ","
             << r.orbit.admissible << "\n";
    }
  }
  curves.Commit();
  std::ostringstream plane;
  plane << "set xlabel 'period T (s)'\nset ylabel 'time of the second impact t_2 (s)'\nset key below\n"
        << "set xrange [0:" << c.periods.back() << "]\nset yrange [0:" << c.periods.back() << "]\n"
        << "plot 'fig06_root_curves.csv' using 1:($3 == 1 ? $2 : 1/0) with points pt 6 ps 0.3 lc rgb '" << kDilated
        << "' title 'trivial root t_2 = T/2 (the dilated 1-ipp)', "
        << "'' using 1:($3 == 0 && $4 == 0 ? $2 : 1/0) with points pt 7 ps 0.2 lc rgb '" << kPotential
        << "' title 'other root, not admissible', "
        << "'' using 1:($3 == 0 && $4 == 1 ? $2 : 1/0) with points pt 7 ps 0.35 lc rgb '" << kTwoStable
        << "' title 'other root, admissible'";
  Draw(c, "fig06_root_curves", plane.str());
}

// The 2-ipp sweep as CSV: every potential orbit with its stability.
void WriteTwoImpact(const Context& c, std::ostream& out) {
  out << "T,t2,energy,potential,admissible,stable,max_multiplier,half_period\n";
  for (const auto& list : c.atlas.two.at) {
    for (const OrbitRecord& r : list) {
      const Orbit& o = r.orbit;
      if (!o.potential) continue;
      out << o.period << "," << o.times[0] << "," << o.energy << "," << o.potential << "," << o.admissible << ","
          << IsStable(r.stability) << ",";
      if (r.stability) out << r.stability->max_modulus;
      out << "," << IsHalfPeriodRoot(o) << "\n";
    }
  }
}

// Fig. 7: 2-ipp energies over (T, t2).
void Figure7(Context& c) {
  report::ResultFile out(c.dir, "fig07_two_impact.csv");
  WriteTwoImpact(c, out.stream());
  const auto [lo, hi] = EnergyRange(c);
  std::ostringstream body;
  // The roots' shadows on the floor (the root curves of fig06_root_curves)
  // and the line t2 = T/2 there: the t2 <-> T - t2 symmetry is read off the
  // floor, the energies above it.
  body << "set xlabel 'period T (s)'\nset ylabel 't_2 (s)'\nset zlabel 'energy E (J)' "
          "rotate\nset logscale z\nset format z '10^{%T}'\nset zrange ["
       << lo << ":" << hi << "]\nset xyplane at " << lo << "\nset view 60,35\nset key top left\n"
       << "set xrange [0:" << c.periods.back() << "]\nset yrange [0:" << c.periods.back() << "]\n"
       << "$half << EOD\n0,0," << lo << "\n" << c.periods.back() << "," << 0.5 * c.periods.back() << "," << lo
       << "\nEOD\n"
       << "splot 'fig07_two_impact.csv' using 1:2:(" << lo << ") with points pt 7 ps 0.1 lc rgb '#DDDDDD' notitle, "
       << "'' using 1:2:($5 == 1 ? " << lo << " : 1/0) with points pt 7 ps 0.15 lc rgb '#F3C9A6' notitle, "
       << "'' using 1:2:3 with points pt 7 ps 0.15 lc rgb '" << kPotential << "' title 'potential', "
       << "'' using 1:2:($5 == 1 && $6 == 1 ? $3 : 1/0) with points pt 7 ps 0.4 lc rgb '" << kTwoStable
       << "' title 'admissible, stable', "
       << "'' using 1:2:($5 == 1 && $6 == 0 ? $3 : 1/0) with points pt 6 ps 0.4 lc rgb '" << kTwoUnstable
       << "' title 'admissible, unstable', "
       << "$half using 1:2:3 with lines dt 2 lw 2 lc rgb '" << kDilated
       << "' title 't_2 = T/2 (on the floor: the roots seen from above)'";
  out.Commit();
  Draw(c, "fig07_two_impact_energy", body.str());
}

void WriteBridges(std::ostream& out, const std::vector<Bridge>& bridges) {
  out << "T,t2,energy_min,energy_max,s_begin,s_end,kind\n";
  for (const Bridge& br : bridges) {
    out << br.period << "," << br.t2 << "," << br.energy_min << "," << br.energy_max << "," << br.s_begin << ","
        << br.s_end << "," << (IsGrazing(br) ? "grazing" : "period-doubling") << "\n";
  }
}

// The layers of a combined frequency-energy plot from a CSV with columns
// family,T,t2,energy,stable (FepTable) and a bridges CSV. Families with one
// orbit per period are lines (solid stable, dashed unstable); the other
// 2-ipp roots are points (filled stable, open unstable).
// `index` >= 0 selects that dataset of both files (gnuplot's `index`).
std::string FepLayers(const std::string& csv, const std::string& bridges, double point_size, int index = -1) {
  std::ostringstream os;
  const std::string ps = std::to_string(point_size), ix = index < 0 ? "" : " index " + std::to_string(index);
  os << "plot '" << csv << "'" << ix << " using 2:(strcol(1) eq '2-ipp' && $5 == 1 ? $4 : 1/0) with points pt 7 ps " << ps
     << " lc rgb '" << kTwoStable << "' title '2-ipp, stable', "
     << "''" << ix << " using 2:(strcol(1) eq '2-ipp' && $5 == 0 ? $4 : 1/0) with points pt 6 ps " << ps << " lc rgb '"
     << kTwoUnstable << "' title '2-ipp, unstable', "
     << "''" << ix << " using 2:(strcol(1) eq '1-ipp' && $5 == 1 ? $4 : 1/0) with lines lw 2.5 lc rgb '" << kOneStable
     << "' title '1-ipp, stable', "
     << "''" << ix << " using 2:(strcol(1) eq '1-ipp' && $5 == 0 ? $4 : 1/0) with lines lw 1.5 dt 2 lc rgb '" << kOneUnstable
     << "' title '1-ipp, unstable', "
     << "''" << ix << " using 2:(strcol(1) eq '2-ipp-half' ? $4 : 1/0) with lines lw 1.5 dt 4 lc rgb '" << kDilated
     << "' title '2-ipp with t_2 = T/2 (1-ipp dilated x2)', "
     << "'" << bridges << "'" << ix << " using 1:3:(0):($4-$3) with vectors nohead lw 3 lc rgb 'black' title 'bridge'";
  return os.str();
}

// The rows of a frequency-energy plot's CSV (family,T,t2,energy,stable) of
// admissible orbits, grouped by family, so that a family with one orbit per
// period (1-ipp; the 2-ipp root t2 = T/2) is drawn as a line, broken (a
// blank line) wherever a period of the grid has no admissible orbit of it.
class FepTable {
 public:
  // `step`: the index of the orbit's period on its grid.
  void Add(int step, const Orbit& o, const std::optional<Stability>& s) {
    if (!o.admissible) return;
    const bool one = o.times.empty(), half = !one && o.impacts == 2 && IsHalfPeriodRoot(o);
    Family& f = one ? one_ : half ? half_ : two_;
    if ((one || half) && f.last >= 0 && step != f.last + 1) f.rows << "\n";
    f.last = step;
    f.rows << (one ? "1-ipp" : half ? "2-ipp-half" : "2-ipp") << "," << o.period << ","
           << (one ? 0.0 : o.times[0]) << "," << o.energy << "," << IsStable(s) << "\n";
  }
  void Write(std::ostream& out) const {
    // One blank line between the families (two would start a new dataset).
    out << "family,T,t2,energy,stable\n";
    bool first = true;
    for (const Family* f : {&one_, &half_, &two_}) {
      if (f->last < 0) continue;
      out << (first ? "" : "\n") << f->rows.str();
      first = false;
    }
  }

 private:
  struct Family {
    std::ostringstream rows;
    int last = -1;
  };
  Family one_, half_, two_;
};

// The admissible 1- and 2-ipp orbits of 401 periods over [t - w, t + w]
// into `table`; returns the range of their energies.
std::pair<double, double> AddOrbitsNear(const Context& c, double t, double w, FepTable& table) {
  double lo = INFINITY, hi = -INFINITY;
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
      }
    }
  }
  return {lo, hi};
}

// Fig. 8: the combined frequency-energy plot.
void Figure8(Context& c) {
  report::ResultFile out(c.dir, "fig08_fep.csv");
  FepTable table;
  for (std::size_t k = 0; k < c.atlas.one.at.size(); ++k) {
    const OrbitRecord& r = c.atlas.one.at[k].front();
    table.Add(static_cast<int>(k), r.orbit, r.stability);
  }
  for (std::size_t k = 0; k < c.atlas.two.at.size(); ++k) {
    for (const OrbitRecord& r : c.atlas.two.at[k]) table.Add(static_cast<int>(k), r.orbit, r.stability);
  }
  table.Write(out.stream());
  report::ResultFile br(c.dir, "fig08_bridges.csv");
  WriteBridges(br.stream(), c.bridges);
  std::ostringstream body;
  body << EnergyAxes(c) << "set key below\n";
  for (std::size_t k = 0; k < c.bridges.size(); ++k) {
    const Bridge& b = c.bridges[k];
    body << "set label 'B" << k + 1 << "' at " << b.period << ", " << b.energy_max << " offset -0.6, 1.1 front\n";
  }
  body << FepLayers("fig08_fep.csv", "fig08_bridges.csv", 0.35);
  out.Commit();
  br.Commit();
  std::ostringstream note;
  for (std::size_t k = 0; k < c.bridges.size(); ++k) {
    note << (k ? "; " : "") << "B" << k + 1 << " " << (IsGrazing(c.bridges[k]) ? "grazing" : "period-doubling")
         << " at T = " << c.bridges[k].period;
  }
  Draw(c, "fig08_fep", body.str(), note.str());
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
  DrawOneOrbit(c, "fig09_two_grazes", g->one, kOneStable, "", GrazeMarks(c, {br.t2, br.period - br.t2}),
               note.str());
}

// The phase sections of Figs. 10, 12, 14: (x_other, x_c, v_c), the paper's
// (x_1, x_2, v_2). A one-dof system has no x_other: time takes its place.
// A family of orbits is a surface there (a nonsmooth mode, or a bridge's
// continuum): each orbit one scan of it, all with the same rows.
struct SectionFamily {
  std::string shade_label;  // what the colour bar measures
  std::vector<std::pair<double, Eigen::MatrixXd>> orbits;  // (shade, OrbitTrajectory)
};
struct SectionCurve {
  std::string title;
  std::string style;  // gnuplot "with ..." clause
  std::vector<Eigen::MatrixXd> trajectories;  // OrbitTrajectory of each orbit
};

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
  auto extend = [&](const Eigen::MatrixXd& tr) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], tr.col(cols[k]).minCoeff());
      hi[k] = std::max(hi[k], tr.col(cols[k]).maxCoeff());
    }
  };
  report::ResultFile out(c.dir, name + ".csv");
  WriteTrajectoryHeader(out.stream(), c);
  for (const auto& [shade, tr] : family.orbits) {
    WriteTrajectory(out.stream(), "family", shade, tr, kSamples + 1);  // OrbitTrajectory's rows per flight
    extend(tr);
    s_lo = std::min(s_lo, shade);
    s_hi = std::max(s_hi, shade);
  }
  for (const SectionCurve& curve : curves) {
    out << "\n";
    for (const Eigen::MatrixXd& tr : curve.trajectories) {
      WriteTrajectory(out.stream(), "curve", 0.0, tr);
      extend(tr);
    }
  }
  out.Commit();
  if (!(s_hi > s_lo)) s_hi = s_lo + 1.0;
  const std::string u = std::to_string(TCol() + cols[0]), w = std::to_string(TCol() + cols[1]),
                    v = std::to_string(TCol() + cols[2]);
  std::ostringstream body;
  body << "set multiplot\nset size 0.56, 1\nset origin 0, 0\n" << kViridis << "set cbrange [" << s_lo << ":" << s_hi << "]\nset cblabel '"
       << family.shade_label << "'\nset colorbox user origin screen 0.565, screen 0.25 size screen 0.02, screen 0.5\n"
       << "set xlabel '" << (c.b.n > 1 ? DofLabel("x", c.other, "m") : std::string("t (s)")) << "'\nset ylabel '"
       << DofLabel("x", c.contact, "m") << "'\nset zlabel '" << DofLabel("v", c.contact, "m/s") << "' rotate\n"
       << "set view 62, 35\nset xyplane relative 0\nset key at screen 0.02, screen 0.99 left top\n"
       << "set pm3d depthorder border lc rgb '#00000030' lw 0.3\n"
       << "$plane << EOD\n"
       << lo[0] << "," << c.b.gap << "," << lo[2] << "\n" << lo[0] << "," << c.b.gap << "," << hi[2] << "\n\n"
       << hi[0] << "," << c.b.gap << "," << lo[2] << "\n" << hi[0] << "," << c.b.gap << "," << hi[2] << "\nEOD\n"
       << "splot '" << name << ".csv' index 0 using " << u << ":" << w << ":" << v << ":2 with pm3d notitle, "
       << "$plane using 1:2:3 with pm3d fillcolor rgb '#A0999999' notitle, "
       << "NaN with lines lw 6 lc rgb '#C0C0C0' title 'obstacle x_c = d'";
  for (std::size_t k = 0; k < curves.size(); ++k) {
    body << ", '" << name << ".csv' index " << k + 1 << " using " << u << ":" << w << ":" << v << " " << curves[k].style << " title '"
         << curves[k].title << "'";
  }
  body << "\nset size 0.34, 1\nset origin 0.66, 0\nunset pm3d\nunset colorbox\nunset key\nset xlabel '" << DofLabel("x", c.contact, "m")
       << "'\nset ylabel '" << DofLabel("v", c.contact, "m/s") << "'\n"
       << "set arrow from " << c.b.gap << ", graph 0 to " << c.b.gap << ", graph 1 nohead dt 2 lc rgb 'black'\n"
       << "plot '" << name << ".csv' index 0 using " << w << ":" << v << ":2 with lines lw 1 lc palette";
  for (std::size_t k = 0; k < curves.size(); ++k) {
    body << ", '' index " << k + 1 << " using " << w << ":" << v << " " << curves[k].style;
  }
  body << "\nunset multiplot";
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
  SectionFamily family{"period T (s)", {}};
  for (int k = 1; k <= 24; ++k) {
    const Orbit o = OneImpactOrbit(c.b, m.period + m.side * m.width * k / 25.0);
    if (!o.admissible || o.energy > 4.0 * mode.energy) break;
    family.orbits.emplace_back(o.period, OrbitTrajectory(c.b, o, kSamples));
  }
  std::ostringstream note;
  note << family.orbits.size() << " 1-ipp orbits, T from " << m.period << " to "
       << (family.orbits.empty() ? m.period : family.orbits.back().first);
  DrawSection(c, "fig10_one_impact_mode", family,
              {{"grazing linear mode", "with lines lw 3 lc rgb 'black'", {OrbitTrajectory(c.b, mode, kSamples)}}},
              note.str());
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
  out << ",t2,energy,arclength\n";
  const Orbit linear = GrazingMode(c.b, mode, period);
  auto write = [&](int index, const Orbit& o, double arclength) {
    const Eigen::MatrixXd tr = OrbitTrajectory(c.b, o, kSamples);
    for (long r = 0; r < tr.rows(); ++r) {
      out << index << "," << o.period;
      for (long k = 0; k < tr.cols(); ++k) out << "," << tr(r, k);
      out << "," << (o.times.empty() ? 0.0 : o.times[0]) << "," << o.energy << "," << arclength << "\n";
    }
    out << "\n";
  };
  write(0, linear, 0.0);
  const int curves = 16;
  std::ostringstream summary;
  for (int j = 1; j <= curves; ++j) {
    const BranchPoint& p = branch[run[(run.size() - 1) * j / curves]];
    const Orbit o = TwoImpactOrbitAt(c.b, p.t2, p.period);
    write(j, o, p.arclength);
    if (j == curves) summary << "last: T = " << o.period << ", t_2 = " << o.times[0];
  }
  double tmin = INFINITY, tmax = -INFINITY;
  for (std::size_t k : run) {
    tmin = std::min(tmin, branch[k].period);
    tmax = std::max(tmax, branch[k].period);
  }
  std::ostringstream body;
  body << "set xlabel 'time t (s)'\nset ylabel '" << XcLabel(c) << "'\nset key below\n"
       << kViridis << "set cbrange [0:" << curves << "]\nset cblabel 'orbit along the branch (0: the grazing mode)'\n"
       << "plot 'fig11_two_impact_mode.csv' using " << TCol() << ":" << XCol(c, c.contact)
       << ":1 with lines lw 1.5 lc palette notitle, " << c.b.gap << " with lines dt 2 lc rgb 'black' title 'd'";
  out.Commit();
  std::ostringstream note;
  note << "from the grazing mode at T = 3 T_i = " << period << " (T_i = " << c.b.Periods()[mode]
       << ", the shortest linear period) to " << summary.str()
       << "; T spans [" << tmin << ", " << tmax << "]";
  Draw(c, "fig11_two_impact_orbits", body.str(), note.str());
  // Fig. 12: the branch's orbits as a surface, finer than Fig. 11's curves.
  SectionFamily family{"arclength s along the root curve (0: the grazing mode)", {}};
  const int scans = 40;
  for (int j = 1; j <= scans; ++j) {
    const BranchPoint& p = branch[run[(run.size() - 1) * j / scans]];
    family.orbits.emplace_back(std::abs(p.arclength), OrbitTrajectory(c.b, TwoImpactOrbitAt(c.b, p.t2, p.period), kSamples));
  }
  DrawSection(c, "fig12_two_impact_mode", family,
              {{"grazing linear mode", "with lines lw 3 lc rgb 'black'", {OrbitTrajectory(c.b, linear, kSamples)}}}, "");
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
    WriteTrajectory(out.stream(), "one_shifted", t, ShiftTrajectory(one_tr, t - br->t2, t));
    for (const auto& [label, f] : {std::pair<const char*, double>{"s20", 0.2}, {"s50", 0.5}, {"s80", 0.8}}) {
      WriteTrajectory(out.stream(), label, t, OrbitTrajectory(c.b, BridgeOrbit(c.b, *br, f * br->s_end), kSamples));
    }
    std::ostringstream body;
    // The ends of the bridge (the grazing orbit and its shift) black, as in
    // Fig. 14; the 2-ipp orbits between shaded by s / s_end on its colour bar.
    body << "set xlabel 'time t (s)'\nset ylabel '" << XcLabel(c) << "'\nset key below\n" << kViridis
         << "set cbrange [0:1]\nset cblabel 's / s_{end} along the bridge (2-ipp, T = T_G)'\n"
         << "plot 'fig13_bridge_orbits.csv' using (strcol(1) eq 'one' ? $3 : 1/0):" << XCol(c, c.contact)
         << " with lines lw 3 lc rgb 'black' title 'grazing 1-ipp orbit (s = 0)', "
         << "'' using (strcol(1) eq 'one_shifted' ? $3 : 1/0):" << XCol(c, c.contact)
         << " with lines lw 3 dt 2 lc rgb 'black' title 'the same, shifted (s = s_{end})'";
    for (int pct : {20, 50, 80}) {
      body << ", '' using (strcol(1) eq 's" << pct << "' ? $3 : 1/0):" << XCol(c, c.contact) << ":(" << pct / 100.0
           << ") with lines lw 1.5 lc palette " << (pct == 20 ? "title '2-ipp, s = 0.2, 0.5, 0.8 s_{end}'" : "notitle");
    }
    body << ", " << c.b.gap << " with lines dt 3 lc rgb 'black' title 'd'";
    out.Commit();
    std::ostringstream note;
    note << "T_G = " << t << ", the shift " << t - br->t2;
    Draw(c, "fig13_bridge_orbits", body.str(), note.str());
  }
  // Fig. 14: the same in the phase section, with neighbouring 1-ipp orbits.
  {
    SectionCurve one{"1-ipp orbits, T near T_G", "with lines lw 1 lc rgb '" + std::string(kOneStable) + "'", {}};
    const double eps = 1e-4 * t;
    const int side = OneImpactOrbit(c.b, t - eps).admissible ? -1 : 1;
    for (int k = 1; k <= 8; ++k) {
      const Orbit o = OneImpactOrbit(c.b, t + side * 0.004 * t * k);
      if (!o.admissible) break;
      one.trajectories.push_back(OrbitTrajectory(c.b, o, kSamples));
    }
    SectionFamily family{"s / s_{end} along the bridge (2-ipp, T = T_G)", {}};
    for (int k = 0; k <= 20; ++k) {
      family.orbits.emplace_back(k / 20.0, OrbitTrajectory(c.b, BridgeOrbit(c.b, *br, br->s_end * k / 20.0), kSamples));
    }
    DrawSection(c, "fig14_bridge_section", family,
                {one, {"grazing 1-ipp orbit (s = 0)", "with lines lw 3 lc rgb 'black'",
                       {OrbitTrajectory(c.b, OneImpactOrbit(c.b, t), kSamples)}}},
                "");
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
    body << "set xlabel 'period T (s)'\nset ylabel 'energy E (J)'\nset key below\n"
         << "set xrange [" << t - w << ":" << t + w << "]\nset yrange [" << e_lo - pad << ":" << e_hi + pad << "]\n"
         << FepLayers("fig15_bridge_fep.csv", "fig15_bridge.csv", 0.6);
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
  body << "set multiplot layout " << rows << "," << cols << "\nunset key\nset xlabel 'period T (s)'\nset ylabel 'energy E (J)'\n";
  for (int k = 0; k < n; ++k) {
    const Bridge& br = c.bridges[k];
    const double w = 0.01 * br.period, height = br.energy_max - br.energy_min;
    FepTable table;
    AddOrbitsNear(c, br.period, w, table);
    table.Write(out.stream());
    out << "\n\n";
    WriteBridges(bo.stream(), {br});
    bo << "\n\n";
    body << "set xrange [" << br.period - w << ":" << br.period + w << "]\nset yrange ["
         << br.energy_min - 0.5 * height << ":" << br.energy_max + 0.5 * height << "]\n"
         << "set label 1 'B" << k + 1 << ": " << (IsGrazing(br) ? "grazing" : "period doubling") << ", T = "
         << std::setprecision(6) << br.period << "' at graph 0.03, graph 0.93 front\n"
         << FepLayers("fig17_bridges_fep.csv", "fig17_bridges.csv", 0.5, k) << "\n";
  }
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
void Figure16(Context& c) {
  const ThreeImpactPick pick = ThreeImpactFamilyExample(c.b, c.atlas);
  if (pick.family.empty()) {
    c.log << "  fig16: " << pick.why_not << "; skipped\n";
    return;
  }
  report::ResultFile out(c.dir, "fig16_three_impact_family.csv");
  out << "T,t2,t3,energy,admissible,stable,max_multiplier\n";
  for (const Orbit& o : pick.family) {
    out << o.period << "," << o.times[0] << "," << o.times[1] << "," << o.energy << "," << o.admissible << ",";
    if (o.admissible) {
      const Stability s = OrbitStability(c.b, o);
      out << (s.defined && s.stable) << "," << s.max_modulus;
    } else {
      out << "0,";
    }
    out << "\n";
  }
  report::ResultFile one(c.dir, "fig16_one_impact.csv");
  one << "T,energy,admissible,stable\n";
  const double width = pick.admissible_to - pick.admissible_from;
  const double t_lo = pick.admissible_from - 0.5 * width, t_hi = pick.admissible_to + 0.5 * width;
  for (const auto& list : c.atlas.one.at) {
    const OrbitRecord& r = list.front();
    if (r.orbit.period >= t_lo && r.orbit.period <= t_hi) {
      one << r.orbit.period << "," << r.orbit.energy << "," << r.orbit.admissible << "," << IsStable(r.stability)
          << "\n";
    }
  }
  report::ResultFile orbit(c.dir, "fig16_orbit.csv");
  WriteTrajectoryHeader(orbit.stream(), c);
  WriteTrajectory(orbit.stream(), "x", pick.start.period, OrbitTrajectory(c.b, pick.start, kSamples));
  double e_hi = 0.0;
  for (const Orbit& o : pick.family) {
    if (o.admissible) e_hi = std::max(e_hi, o.energy);
  }
  std::ostringstream body, period_label;
  period_label << std::setprecision(4) << pick.start.period;
  body << "set multiplot layout 1,2\n";
  // The ends of the admissible stretch, dotted.
  for (double t : {pick.admissible_from, pick.admissible_to}) {
    body << "set arrow from " << t << ", graph 0 to " << t << ", graph 1 nohead dt 3 lc rgb 'black'\n";
  }
  body
       << "set xlabel 'period T (s)'\nset ylabel 'energy E (J)'\nset key below\n"
       << "set xrange [" << t_lo << ":" << t_hi << "]\nset yrange [0:" << 1.5 * e_hi << "]\n"
       << "plot 'fig16_three_impact_family.csv' using 1:($5 == 0 ? $4 : 1/0) with lines lw 1.5 dt 3 lc rgb '" << kNotAdmissible
       << "' title '3-ipp, not admissible', "
       << "'' using 1:($5 == 1 && $6 == 0 ? $4 : 1/0) with lines lw 2 dt 5 lc rgb '" << kThree << "' title '3-ipp, unstable', "
       << "'' using 1:($5 == 1 && $6 == 1 ? $4 : 1/0) with lines lw 3 lc rgb '" << kThree << "' title '3-ipp, stable', "
       << "'fig16_one_impact.csv' using 1:($3 == 1 && $4 == 1 ? $2 : 1/0) with lines lw 2.5 lc rgb '" << kOneStable
       << "' title '1-ipp, stable', "
       << "'' using 1:($3 == 1 && $4 == 0 ? $2 : 1/0) with lines lw 1.5 dt 2 lc rgb '" << kOneUnstable
       << "' title '1-ipp, unstable'\n"
       << "unset arrow\nset autoscale y\nset xrange [0:" << pick.start.period << "]\n"
       << "set xlabel 'time t (s)'\nset ylabel '" << XcLabel(c) << "'\n"
       << "plot 'fig16_orbit.csv' using " << TCol() << ":" << XCol(c, c.contact)
       << " with lines lw 2 lc rgb '" << kThree << "' title 'x_c(t), T = " << period_label.str() << "', " << c.b.gap << " with lines dt 2 lc rgb 'black' title 'obstacle d'\n"
       << "unset multiplot";
  out.Commit();
  one.Commit();
  orbit.Commit();
  std::ostringstream note;
  note << "admissible for T in [" << std::setprecision(9) << pick.admissible_from << ", " << pick.admissible_to
       << "], the orbit drawn at T = " << pick.start.period;
  Draw(c, "fig16_three_impact_family", body.str(), note.str());
}

// Fig. 18 (several contacts, issue 24): the frequency-energy plot of every
// family of one and two impacts per period, one colour per impact sequence:
// (j) for each contact, (j, j) and (j, k), j < k ((k, j) is (j, k) shifted
// by t2). Admissible orbits only, over the atlas's grid; 1-impact families
// as lines (solid stable, dashed unstable), 2-impact ones as points (filled
// stable, open unstable). With a rigid-body mode (a free mass in a cavity)
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
  os << "sequence,index,T,t2,energy,stable\n";
  std::vector<std::string> labels, titles;
  SweepOptions opt;
  opt.stability = StabilityPolicy::kAdmissible;
  double lo = INFINITY, hi = -INFINITY;
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
    labels.push_back(label.str());
    titles.push_back(title.str());
    opt.sequence = seq;
    int last = -2;
    for (std::size_t i = 0; i < c.periods.size(); ++i) {
      for (const OrbitRecord& r : OrbitsAt(c.b, c.periods[i], static_cast<int>(seq.size()), opt)) {
        if (!r.orbit.admissible) continue;
        // A 1-impact family is a line: broken where a period has no admissible orbit.
        if (seq.size() == 1 && last >= 0 && static_cast<int>(i) != last + 1) os << "\n";
        last = static_cast<int>(i);
        os << labels.back() << "," << s << "," << r.orbit.period << "," << (seq.size() == 1 ? 0.0 : r.orbit.times[0]) << ","
           << r.orbit.energy << "," << IsStable(r.stability) << "\n";
        lo = std::min(lo, r.orbit.energy);
        hi = std::max(hi, r.orbit.energy);
      }
    }
  }
  out.Commit();
  if (!(lo < hi)) {
    c.log << "  fig18_sequences_fep: no admissible orbit of any sequence on the grid: not drawn\n";
    return;
  }
  static const char* colours[] = {"#1b9e77", "#d95f02", "#7570b3", "#e7298a", "#66a61e", "#e6ab02", "#a6761d", "#666666"};
  std::ostringstream body;
  body << "set logscale y\nset format y '10^{%T}'\nset yrange [" << 0.5 * lo << ":" << 2.0 * hi << "]\n"
       << "set xlabel 'period T (s)'\nset ylabel 'energy E (J)'\nset xrange [0:" << c.periods.back() << "]\n"
       << "set key outside right\nplot ";
  for (std::size_t s = 0; s < sequences.size(); ++s) {
    const std::string colour = colours[s % 8], &title = titles[s];
    std::ostringstream select;
    select << "(strcol(1) eq '" << labels[s] << "' && $6 == ";
    const std::string sel = select.str();
    if (s > 0) body << ", ";
    if (sequences[s].size() == 1) {
      body << "'fig18_sequences_fep.csv' using 3:" << sel << "1 ? $5 : 1/0) with lines lw 2.5 lc rgb '" << colour
           << "' title '" << title << " stable', '' using 3:" << sel << "0 ? $5 : 1/0) with lines lw 1.5 dt 2 lc rgb '"
           << colour << "' title '" << title << " unstable'";
    } else {
      body << "'fig18_sequences_fep.csv' using 3:" << sel << "1 ? $5 : 1/0) with points pt 7 ps 0.35 lc rgb '" << colour
           << "' title '" << title << " stable', '' using 3:" << sel << "0 ? $5 : 1/0) with points pt 6 ps 0.35 lc rgb '"
           << colour << "' title '" << title << " unstable'";
    }
  }
  body << "\n";
  Draw(c, "fig18_sequences_fep", body.str(), std::to_string(sequences.size()) + " impact sequences");
}

FiguresResult DrawPaperFigures(const AnalysisBasis& b, int contact, const Atlas& atlas, const OutputDir& dir,
                               std::ostream& log) {
  Context c{.b = b,
            .contact = contact,
            .other = contact == 0 ? (b.n > 1 ? 1 : 0) : 0,
            .dir = dir,
            .atlas = atlas,
            .log = log};
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
  Figure16(c);
  Figure17(c);
  Figure18(c);
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
  std::string integrator_list;
  for (const std::string& i : integrators) integrator_list += (integrator_list.empty() ? "" : " ") + i;
  int failed = 0;
  for (const std::string& name : case_names) {
    double smallest = std::numeric_limits<double>::infinity();
    for (const WorkPrecisionRow& r : rows) {
      if (r.case_name == name && r.error > 0.0 && std::isfinite(r.error)) smallest = std::min(smallest, r.error);
    }
    const double floor = std::isfinite(smallest) ? 0.1 * smallest : 1e-16;
    std::ostringstream body;
    // work_precision.csv: case 1, integrator 2, setting 3, error 4, cpu_s 5,
    // impacts 6, steps 7, expected_impacts 8.
    body << "set datafile separator ','\nset logscale xy\nset format y '10^{%T}'\nset format x '10^{%T}'\n"
         << "set xlabel 'CPU time per run (s)'\nset ylabel 'relative error of the final state (vs exact, root\\_tol 1e-14)'\n"
         << "set key outside right\nset grid\n"
         << "floor = " << floor << "\n"
         << "set arrow from graph 0, first floor to graph 1, first floor nohead dt 3 lc rgb '#999999'\n"
         << "set label 'error 0 (drawn at this floor)' at graph 0.02, first floor offset 0, 0.7 font ',8'\n"
         << "plot for [i in '" << integrator_list << "'] 'work_precision.csv' "
         << "using (strcol(1) eq '" << name << "' && strcol(2) eq i && $4 > 0 ? $5 : 1/0):4 "
         << "with linespoints lw 2 pt 7 title i, \\\n"
         << "  for [i in '" << integrator_list << "'] '' "
         << "using (strcol(1) eq '" << name << "' && strcol(2) eq i && $4 == 0 ? $5 : 1/0):(floor) "
         << "with points pt 6 ps 1.5 lw 2 lc rgb '#555555' notitle, \\\n"
         << "  '' using (strcol(1) eq '" << name << "' && $6 != $8 ? $5 : 1/0):($4 > 0 ? $4 : floor) "
         << "with points pt 2 ps 2.5 lw 2 lc rgb 'black' title 'wrong impact count'\n";
    const ChartStatus chart = DrawChart(dir, "work_precision_" + name, body.str());
    if (!chart.drawn) {
      log << "work_precision_" << name << " not drawn: " << chart.message << "\n";
      ++failed;
    }
  }
  return failed;
}

int DrawResponseCharts(const OutputDir& dir, const std::vector<ResponseRow>& rows, int dofs, bool backbone,
                       bool frequency, int periods, std::ostream& log) {
  double e_min = std::numeric_limits<double>::infinity(), e_max = 0.0, x_max = 0.0;
  for (const ResponseRow& r : rows) {
    if (r.orbit.energy > 0.0) e_min = std::min(e_min, r.orbit.energy);
    e_max = std::max(e_max, r.orbit.energy);
    x_max = std::max(x_max, r.orbit.max_xc);
  }
  if (rows.empty() || !(e_max > 0.0)) return 0;
  // response.csv columns (1-based, tables.h): w 1, amplitude 2, energy 5,
  // max_xc 6, admissible 8, stable 9, branch 12 + 2N.
  const int branch_col = 12 + 2 * dofs;
  const int x = frequency ? 1 : 2;
  int failed = 0;
  for (const auto& [name, col, label] : {std::tuple<std::string, int, std::string>{"response_energy", 5, "mean energy (J)"},
                                         {"response_max_xc", 6, "max x_c (m)"}}) {
    std::ostringstream body;
    body << "set datafile separator ','\nset grid\nset key outside right top\n"
         << "set xlabel '" << (frequency ? "forcing frequency w (rad/s)" : "forcing amplitude a (N)") << "'\n"
         << "set ylabel '" << label << "'\n"
         << (col == 5 ? "set logscale y\nset yrange [" + std::to_string(0.5 * e_min) + ":" + std::to_string(3.0 * e_max) + "]\n"
                      : "set yrange [0:" + std::to_string(1.1 * x_max) + "]\n")
         << "okabe = '#E69F00 #56B4E9 #009E73 #0072B2 #D55E00 #CC79A7 #F0E442'\n"
         << "stats 'response.csv' using " << branch_col << " nooutput\n"
         << "nb = int(STATS_max)\n"
         << "plot for [b=1:nb] 'response.csv' using ($" << branch_col << "==b && $8==0 ? $" << x << " : 1/0):" << col
         << " with lines lw 0.8 lc rgb '#BBBBBB' title (b==1 ? 'not admissible' : ''), \\\n"
         << "  for [b=1:nb] '' using ($" << branch_col << "==b && $8==1 && $9==1 ? $" << x << " : 1/0):" << col
         << " with lines lw 2.5 lc rgb word(okabe, (b-1)%7+1) title (b==1 ? 'admissible, stable' : ''), \\\n"
         << "  for [b=1:nb] '' using ($" << branch_col << "==b && $8==1 && $9==0 ? $" << x << " : 1/0):" << col
         << " with lines lw 1.5 dt 2 lc rgb word(okabe, (b-1)%7+1) title (b==1 ? 'admissible, unstable' : '')";
    if (backbone && col == 5) {
      body << ", \\\n  'backbone.csv' using ($4==1 && $5==1 ? " << periods << "*$1 : 1/0):3 with lines lw 2 lc rgb 'black' "
              "title 'nonsmooth mode (stable)', \\\n"
           << "  'backbone.csv' using ($4==1 && $5==0 ? " << periods << "*$1 : 1/0):3 with lines lw 1.5 dt 3 lc rgb 'black' "
              "title 'nonsmooth mode (unstable)'";
    }
    // response_points.csv: w 1, amplitude 2, kind 3, energy 4, max_xc 6.
    const int pcol = col == 5 ? 4 : 6;
    body << ", \\\n  for [k in 'fold period-doubling grazing zero-velocity peak'] 'response_points.csv' using "
         << "(strcol(3) eq k ? $" << x << " : 1/0):" << pcol << " with points pt (k eq 'peak' ? 7 : (k eq 'fold' ? 5 : "
         << "(k eq 'grazing' ? 9 : (k eq 'period-doubling' ? 13 : 3)))) ps 1.2 lc rgb 'black' title k\n";
    const ChartStatus chart = DrawChart(dir, name, body.str());
    if (!chart.drawn) {
      log << name << " not drawn: " << chart.message << "\n";
      ++failed;
    }
  }
  return failed;
}

}  // namespace nsmodal::report
