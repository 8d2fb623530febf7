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
#include "nsmodal/scene.h"
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

// The data files must be closed (flushed) before this is called.
void Draw(Context& c, const std::string& name, const std::string& body) {
  // Offsets keep a curve that touches d off the frame of an autoscaled axis.
  const std::string setup = "set datafile separator ','\nset grid\nset offsets graph 0, graph 0, graph 0.05, graph 0.05\n";
  const report::ChartStatus s = report::DrawChart(c.dir, name, setup + body);
  (s.drawn ? c.drawn : c.failed) += 1;
  c.log << "  " << name << (s.drawn ? "" : ": not drawn: " + s.message) << "\n";
}

bool IsStable(const std::optional<Stability>& s) { return s && s->stable; }


// Trajectory rows of one orbit: label, T, then OrbitTrajectory's columns.
void WriteTrajectoryHeader(std::ostream& os, const Context& c) {
  os << "curve,T,t";
  for (int i = 1; i <= c.b.n; ++i) os << ",x" << i;
  for (int i = 1; i <= c.b.n; ++i) os << ",v" << i;
  os << "\n";
}
void WriteTrajectory(std::ostream& os, const std::string& label, double period, const Eigen::MatrixXd& tr) {
  for (long r = 0; r < tr.rows(); ++r) {
    os << label << "," << period;
    for (long k = 0; k < tr.cols(); ++k) os << "," << tr(r, k);
    os << "\n";
  }
  os << "\n";
}

// Columns of a trajectory CSV (1-based for gnuplot): t, x_i, v_i.
int TCol() { return 3; }
int XCol(const Context&, int dof) { return 4 + dof; }
int VCol(const Context& c, int dof) { return 4 + c.b.n + dof; }


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

// A chart of x_c(t) over one period of one orbit (Figs. 2, 5, 9): the orbit's
// samples to DIR/NAME.csv, the chart with the obstacle at d. `title` may hold
// "\\n" (a gnuplot line break); `extra` is gnuplot set-up drawn under it.
void DrawOneOrbit(Context& c, const std::string& name, const Orbit& o, const std::string& title,
                  const std::string& extra = "") {
  report::ResultFile out(c.dir, name + ".csv");
  WriteTrajectoryHeader(out.stream(), c);
  WriteTrajectory(out.stream(), "x", o.period, OrbitTrajectory(c.b, o, kSamples));
  out.Commit();
  std::ostringstream body;
  body << "set xlabel 'time t (s)'\nset ylabel '" << XcLabel(c) << "'\nset key below\nset title \"" << title
       << "\"\n"
       << extra << "plot '" << name << ".csv' using " << TCol() << ":" << XCol(c, c.contact)
       << " with lines lw 2 lc rgb '" << kOneStable << "' title 'x_c(t)', " << c.b.gap
       << " with lines dt 2 lc rgb 'black' title 'obstacle d'";
  Draw(c, name, body.str());
}

// Fig. 2: a potential 2-ipp orbit that is not admissible.
void Figure2(Context& c) {
  const Orbit* pick = NotAdmissibleExample(c.atlas, c.b.gap);
  if (!pick) {
    c.log << "  fig02: no potential, non-admissible 2-ipp orbit in the sweep; skipped\n";
    return;
  }
  std::ostringstream title;
  title << "Fig. 2: potential, not admissible 2-ipp orbit, T = " << pick->period << ", t_2 = " << pick->times[0]
        << "\\nNC2 holds at the impacts; NC3 fails: x_c exceeds d by " << pick->max_excess;
  DrawOneOrbit(c, "fig02_not_admissible", *pick, title.str());
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
       << "set title 'Fig. 3: energies of the T-periodic 1-ipp orbits'\n"
       << "plot 'fig03_one_impact.csv' using 1:($3 == 1 ? $2 : 1/0) with points pt 7 ps 0.25 lc rgb '" << kPotential
       << "' title 'potential', "
       << "'' using 1:($4 == 1 && $5 == 1 ? $2 : 1/0) with points pt 7 ps 0.35 lc rgb '" << kOneStable
       << "' title 'admissible, stable', "
       << "'' using 1:($4 == 1 && $5 == 0 ? $2 : 1/0) with points pt 7 ps 0.35 lc rgb '" << kOneUnstable << "'"
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
       << "set title 'Fig. 4: linear modal transition at T = " << m.period << " (1-ipp)'\n"
       << "plot 'fig04_modal_transition.csv' using (strcol(1) eq 'admissible' ? $3/$2 : 1/0):" << XCol(c, c.contact)
       << " with lines lw 2 lc rgb '" << kOneStable << "' title 'T = " << in.period << " (admissible)', "
       << "'' using (strcol(1) eq 'modal' ? $3/$2 : 1/0):" << XCol(c, c.contact)
       << " with lines lw 2 lc rgb 'black' title 'T = " << m.period << " (grazing linear mode)', "
       << "'' using (strcol(1) eq 'not_admissible' ? $3/$2 : 1/0):" << XCol(c, c.contact)
       << " with lines lw 2 dt 2 lc rgb '" << kNotAdmissible << "' title 'T = " << beyond.period
       << " (x_c > d: not admissible)', "
       << c.b.gap << " with lines dt 2 lc rgb 'gray40' title 'd'";
  out.Commit();
  Draw(c, "fig04_modal_transition", body.str());
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
  std::ostringstream title;
  title << "Fig. 5: grazing transition T_G = " << br.period << ": x_c touches d at t = " << br.t2;
  DrawOneOrbit(c, "fig05_grazing_transition", OneImpactOrbit(c.b, br.period), title.str());
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
  body << "set multiplot layout 2,5 title 'Fig. 6: det A_2(t_2, T) against t_2; roots: t_2 = T/2 open, others filled'\n"
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
        << "plot 'fig06_root_curves.csv' using 1:($3 == 1 ? $2 : 1/0) with points pt 7 ps 0.2 lc rgb '" << kDilated
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
  body << "set xlabel 'period T (s)'\nset ylabel 'time of the second impact t_2 (s)'\nset zlabel 'energy E (J)' "
          "rotate\nset logscale z\nset format z '10^{%T}'\nset zrange ["
       << lo << ":" << hi << "]\nset xyplane at " << lo << "\nset view 60,35\nset key top left\n"
       << "set title 'Fig. 7: energies of the T-periodic 2-ipp orbits over (T, t_2)'\n"
       << "splot 'fig07_two_impact.csv' using 1:2:3 with points pt 7 ps 0.15 lc rgb '" << kPotential
       << "' title 'potential', "
       << "'' using 1:2:($5 == 1 && $6 == 1 ? $3 : 1/0) with points pt 7 ps 0.3 lc rgb '" << kTwoStable
       << "' title 'admissible, stable', "
       << "'' using 1:2:($5 == 1 && $6 == 0 ? $3 : 1/0) with points pt 7 ps 0.3 lc rgb '" << kTwoUnstable
       << "' title 'admissible, unstable'";
  out.Commit();
  Draw(c, "fig07_two_impact_energy", body.str());
}

void WriteBridges(const Context& c, std::ostream& out) {
  out << "T,t2,energy_min,energy_max,s_begin,s_end,kind\n";
  for (const Bridge& br : c.bridges) {
    out << br.period << "," << br.t2 << "," << br.energy_min << "," << br.energy_max << "," << br.s_begin << ","
        << br.s_end << "," << (IsGrazing(br) ? "grazing" : "period-doubling") << "\n";
  }
}

// The layers of a combined frequency-energy plot from a CSV with columns
// family,T,t2,energy,stable and a bridges CSV.
std::string FepLayers(const std::string& csv, const std::string& bridges, double point_size) {
  std::ostringstream os;
  const std::string ps = std::to_string(point_size);
  os << "plot '" << csv << "' using 2:(strcol(1) eq '2-ipp' && $5 == 1 ? $4 : 1/0) with points pt 7 ps " << ps
     << " lc rgb '" << kTwoStable << "' title '2-ipp, stable', "
     << "'' using 2:(strcol(1) eq '2-ipp' && $5 == 0 ? $4 : 1/0) with points pt 7 ps " << ps << " lc rgb '"
     << kTwoUnstable << "' title '2-ipp, unstable', "
     << "'' using 2:(strcol(1) eq '1-ipp' && $5 == 1 ? $4 : 1/0) with points pt 7 ps " << ps << " lc rgb '"
     << kOneStable << "' title '1-ipp, stable', "
     << "'' using 2:(strcol(1) eq '1-ipp' && $5 == 0 ? $4 : 1/0) with points pt 7 ps " << ps << " lc rgb '"
     << kOneUnstable << "' title '1-ipp, unstable', "
     << "'' using 2:(strcol(1) eq '2-ipp-half' ? $4 : 1/0) with points pt 7 ps " << point_size * 0.5
     << " lc rgb '" << kDilated << "' title '2-ipp with t_2 = T/2 (1-ipp dilated x2)', "
     << "'" << bridges << "' using 1:3:(0):($4-$3) with vectors nohead lw 3 lc rgb 'black' title 'bridge'";
  return os.str();
}

void WriteFepRow(std::ostream& out, const char* family, const Orbit& o, const std::optional<Stability>& s) {
  out << family << "," << o.period << "," << (o.times.empty() ? 0.0 : o.times[0]) << "," << o.energy << ","
      << IsStable(s) << "\n";
}

// Fig. 8: the combined frequency-energy plot.
void Figure8(Context& c) {
  report::ResultFile out(c.dir, "fig08_fep.csv");
  out << "family,T,t2,energy,stable\n";
  for (const auto& list : c.atlas.one.at) {
    const OrbitRecord& r = list.front();
    if (r.orbit.admissible) WriteFepRow(out.stream(), "1-ipp", r.orbit, r.stability);
  }
  for (const auto& list : c.atlas.two.at) {
    for (const OrbitRecord& r : list) {
      const Orbit& o = r.orbit;
      if (!o.admissible) continue;
      WriteFepRow(out.stream(), IsHalfPeriodRoot(o) ? "2-ipp-half" : "2-ipp", o, r.stability);
    }
  }
  report::ResultFile br(c.dir, "fig08_bridges.csv");
  WriteBridges(c, br.stream());
  std::ostringstream body;
  body << EnergyAxes(c) << "set key below\n"
       << "set title 'Fig. 8: admissible 1-ipp and 2-ipp orbits (frequency-energy plot)'\n"
       << FepLayers("fig08_fep.csv", "fig08_bridges.csv", 0.35);
  out.Commit();
  br.Commit();
  Draw(c, "fig08_fep", body.str());
}

// Fig. 9: a 1-ipp orbit with two grazes, admissible as a 3-ipp orbit too.
void Figure9(Context& c) {
  const std::optional<TwoGrazes> g = TwoGrazesExample(c.b, c.atlas);
  if (!g) {
    c.log << "  fig09: no grazing orbit admissible as a 3-ipp orbit in the sweep; skipped\n";
    return;
  }
  const Bridge& br = *g->bridge;
  std::ostringstream title, arrows;
  title << "Fig. 9: one impact and two grazes (t = " << br.t2 << ", " << br.period - br.t2 << "), T = " << br.period
        << "\\nadmissible as a 1-ipp and as a 3-ipp orbit (NC2 residual " << g->three.nc2_residual << ")";
  for (double t : {br.t2, br.period - br.t2}) {
    arrows << "set arrow from " << t << ", graph 0 to " << t << ", graph 1 nohead dt 3 lc rgb 'gray50'\n";
  }
  DrawOneOrbit(c, "fig09_two_grazes", g->one, title.str(), arrows.str());
}

// The phase section of Figs. 10, 12, 14: (x_other, x_c, v_c), the paper's
// (x_1, x_2, v_2). A one-dof system has no x_other: time takes its place.
std::string SectionAxes(const Context& c) {
  std::ostringstream os;
  os << "set xlabel '" << (c.b.n > 1 ? DofLabel("x", c.other, "m") : std::string("t (s)")) << "'\nset ylabel '"
     << DofLabel("x", c.contact, "m") << "'\nset zlabel '" << DofLabel("v", c.contact, "m/s")
     << "' rotate\nset view 65,40\n";
  return os.str();
}
int SectionXCol(const Context& c) { return c.b.n > 1 ? XCol(c, c.other) : TCol(); }
std::string SectionUsing(const Context& c) {
  return std::to_string(SectionXCol(c)) + ":" + std::to_string(XCol(c, c.contact)) + ":" +
         std::to_string(VCol(c, c.contact));
}

// Fig. 10: the 1-ipp nonsmooth mode next to the modal transition of Fig. 4.
void Figure10(Context& c, const ModalPick& m) {
  if (m.side == 0) {
    c.log << "  fig10: no modal transition bounds an admissible zone; skipped\n";
    return;
  }
  report::ResultFile out(c.dir, "fig10_one_impact_mode.csv");
  WriteTrajectoryHeader(out.stream(), c);
  const Orbit mode = GrazingMode(c.b, ModeOf(c.b, m.period), m.period);
  WriteTrajectory(out.stream(), "modal", m.period, OrbitTrajectory(c.b, mode, kSamples));
  // Orbits across the zone, stopping where the energy passes 4 times the
  // mode's (towards a singular transition it diverges).
  int drawn = 0;
  for (int k = 1; k <= 24; ++k) {
    const Orbit o = OneImpactOrbit(c.b, m.period + m.side * m.width * k / 25.0);
    if (!o.admissible || o.energy > 4.0 * mode.energy) break;
    WriteTrajectory(out.stream(), "orbit", o.period, OrbitTrajectory(c.b, o, kSamples));
    ++drawn;
  }
  std::ostringstream body;
  body << SectionAxes(c) << "set key top left\n"
       << "set title 'Fig. 10: " << drawn << " 1-ipp orbits of the nonsmooth mode next to T = " << m.period
       << "'\nsplot 'fig10_one_impact_mode.csv' using (strcol(1) eq 'orbit' ? $" << SectionXCol(c)
       << " : 1/0):" << XCol(c, c.contact) << ":" << VCol(c, c.contact) << " with lines lw 1 lc rgb '" << kOneStable
       << "' title '1-ipp orbits', '' using (strcol(1) eq 'modal' ? $" << SectionXCol(c)
       << " : 1/0):" << XCol(c, c.contact) << ":" << VCol(c, c.contact)
       << " with lines lw 3 lc rgb 'black' title 'grazing linear mode'";
  out.Commit();
  Draw(c, "fig10_one_impact_mode", body.str());
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
       << "set title \"Fig. 11: 2-ipp orbits along the branch from the grazing linear mode, T = 3 T_i = " << period
       << " (dark),\\nto " << summary.str() << " (yellow); T spans [" << tmin << ", " << tmax << "]\"\n"
       << "plot 'fig11_two_impact_mode.csv' using " << TCol() << ":" << XCol(c, c.contact)
       << ":1 with lines lw 1.5 lc palette notitle, " << c.b.gap << " with lines dt 2 lc rgb 'black' title 'd'";
  out.Commit();
  Draw(c, "fig11_two_impact_orbits", body.str());
  std::ostringstream body12;
  body12 << SectionAxes(c) << kViridis << "set cbrange [0:" << curves
         << "]\nset cblabel 'orbit along the branch (0: the grazing mode)'\nset title 'Fig. 12: the same 2-ipp orbits in the phase section: a "
            "nonsmooth mode'\n"
         << "splot 'fig11_two_impact_mode.csv' using " << SectionUsing(c) << ":1 with lines lw 1.5 lc palette notitle";
  Draw(c, "fig12_two_impact_mode", body12.str());
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
    body << "set xlabel 'time t (s)'\nset ylabel '" << XcLabel(c) << "'\nset key below\n"
         << "set title \"Fig. 13: the continuum of 2-ipp orbits of period T_G = " << t
         << "\\nbetween the grazing 1-ipp orbit and its shift by " << t - br->t2 << "\"\n"
         << "plot 'fig13_bridge_orbits.csv' using (strcol(1) eq 'one' ? $3 : 1/0):" << XCol(c, c.contact)
         << " with lines lw 3 lc rgb '" << kOneStable << "' title '1-ipp (s = 0)', "
         << "'' using (strcol(1) eq 'one_shifted' ? $3 : 1/0):" << XCol(c, c.contact)
         << " with lines lw 3 dt 2 lc rgb '" << kOneStable << "' title '1-ipp shifted (s = s_{end})'";
    const char* colours[] = {"#E69F00", "#D55E00", "#8C3A00"};  // the 2-ipp hue, light to dark along s
    int k = 0;
    for (int pct : {20, 50, 80}) {
      body << ", '' using (strcol(1) eq 's" << pct << "' ? $3 : 1/0):" << XCol(c, c.contact)
           << " with lines lw 1.5 lc rgb '" << colours[k++] << "' title '2-ipp, s = 0." << pct / 10 << " s_{end}'";
    }
    body << ", " << c.b.gap << " with lines dt 3 lc rgb 'black' title 'd'";
    out.Commit();
    Draw(c, "fig13_bridge_orbits", body.str());
  }
  // Fig. 14: the same in the phase section, with neighbouring 1-ipp orbits.
  {
    report::ResultFile out(c.dir, "fig14_bridge_section.csv");
    WriteTrajectoryHeader(out.stream(), c);
    const double eps = 1e-4 * t;
    const int side = OneImpactOrbit(c.b, t - eps).admissible ? -1 : 1;
    for (int k = 1; k <= 8; ++k) {
      const Orbit o = OneImpactOrbit(c.b, t + side * 0.004 * t * k);
      if (!o.admissible) break;
      WriteTrajectory(out.stream(), "one", o.period, OrbitTrajectory(c.b, o, kSamples));
    }
    for (int k = 1; k < 10; ++k) {
      WriteTrajectory(out.stream(), "two", t, OrbitTrajectory(c.b, BridgeOrbit(c.b, *br, br->s_end * k / 10.0), kSamples));
    }
    WriteTrajectory(out.stream(), "grazing", t, OrbitTrajectory(c.b, OneImpactOrbit(c.b, t), kSamples));
    const int u = SectionXCol(c);
    std::ostringstream body;
    body << SectionAxes(c) << "set key top left\n"
         << "set title 'Fig. 14: the bridge at T_G = " << t << " in the phase section'\n"
         << "splot 'fig14_bridge_section.csv' using (strcol(1) eq 'one' ? $" << u << " : 1/0):" << XCol(c, c.contact)
         << ":" << VCol(c, c.contact) << " with lines lw 1 lc rgb '" << kOneStable << "' title '1-ipp, T near T_G', "
         << "'' using (strcol(1) eq 'two' ? $" << u << " : 1/0):" << XCol(c, c.contact) << ":" << VCol(c, c.contact)
         << " with lines lw 1 lc rgb '" << kTwoStable << "' title '2-ipp, T = T_G (bridge)', "
         << "'' using (strcol(1) eq 'grazing' ? $" << u << " : 1/0):" << XCol(c, c.contact) << ":"
         << VCol(c, c.contact) << " with lines lw 3 lc rgb 'black' title 'grazing 1-ipp orbit'";
    out.Commit();
    Draw(c, "fig14_bridge_section", body.str());
  }
  // Fig. 15: zoom of the frequency-energy plot on the bridge.
  {
    const double w = 0.01 * t;
    report::ResultFile out(c.dir, "fig15_bridge_fep.csv");
    out << "family,T,t2,energy,stable\n";
    double lo = br->energy_min, hi = br->energy_max;
    SweepOptions admissible_only;
    admissible_only.stability = StabilityPolicy::kAdmissible;
    for (int j = 0; j <= 400; ++j) {
      const double p = t - w + 2 * w * j / 400.0;
      for (int impacts : {1, 2}) {
        for (const OrbitRecord& r : OrbitsAt(c.b, p, impacts, admissible_only)) {
          const Orbit& o = r.orbit;
          if (!o.admissible) continue;
          WriteFepRow(out.stream(), impacts == 1 ? "1-ipp" : IsHalfPeriodRoot(o) ? "2-ipp-half" : "2-ipp", o,
                      r.stability);
          lo = std::min(lo, o.energy);
          hi = std::max(hi, o.energy);
        }
      }
    }
    report::ResultFile bo(c.dir, "fig15_bridge.csv");
    bo << "T,t2,energy_min,energy_max,s_begin,s_end,kind\n"
       << t << "," << br->t2 << "," << br->energy_min << "," << br->energy_max << "," << br->s_begin << ","
       << br->s_end << ",grazing\n";
    const double pad = 0.1 * (hi - lo);
    std::ostringstream body;
    body << "set xlabel 'period T (s)'\nset ylabel 'energy E (J)'\nset key below\n"
         << "set xrange [" << t - w << ":" << t + w << "]\nset yrange [" << lo - pad << ":" << hi + pad << "]\n"
         << "set title 'Fig. 15: the bridge at T_G = " << t << ": E from " << br->energy_min << " to "
         << br->energy_max << "'\n"
         << FepLayers("fig15_bridge_fep.csv", "fig15_bridge.csv", 0.6);
    out.Commit();
    bo.Commit();
    Draw(c, "fig15_bridge_fep", body.str());
  }
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
  one << "T,energy,stable\n";
  const double width = pick.admissible_to - pick.admissible_from;
  const double t_lo = pick.admissible_from - 0.5 * width, t_hi = pick.admissible_to + 0.5 * width;
  for (const auto& list : c.atlas.one.at) {
    const OrbitRecord& r = list.front();
    if (r.orbit.admissible && r.orbit.period >= t_lo && r.orbit.period <= t_hi) {
      one << r.orbit.period << "," << r.orbit.energy << "," << IsStable(r.stability) << "\n";
    }
  }
  report::ResultFile orbit(c.dir, "fig16_orbit.csv");
  WriteTrajectoryHeader(orbit.stream(), c);
  WriteTrajectory(orbit.stream(), "x", pick.start.period, OrbitTrajectory(c.b, pick.start, kSamples));
  double e_lo = INFINITY, e_hi = 0.0;
  for (const Orbit& o : pick.family) {
    if (o.admissible) {
      e_lo = std::min(e_lo, o.energy);
      e_hi = std::max(e_hi, o.energy);
    }
  }
  std::ostringstream body, period_label;
  period_label << std::setprecision(4) << pick.start.period;
  body << "set multiplot layout 1,2\n";
  // The ends of the admissible stretch, dotted.
  for (double t : {pick.admissible_from, pick.admissible_to}) {
    body << "set arrow from " << t << ", graph 0 to " << t << ", graph 1 nohead dt 3 lc rgb 'black'\n";
  }
  body
       << "set xlabel 'period T (s)'\nset ylabel 'energy E (J)'\nset logscale y\nset key below\n"
       << "set xrange [" << t_lo << ":" << t_hi << "]\nset yrange [" << 0.5 * e_lo << ":" << 3.0 * e_hi << "]\n"
       << "plot 'fig16_three_impact_family.csv' using 1:($5 == 0 ? $4 : 1/0) with lines lw 1 lc rgb '" << kPotential
       << "' title '3-ipp, not admissible', "
       << "'' using 1:($5 == 1 && $6 == 0 ? $4 : 1/0) with lines lw 2 dt 2 lc rgb '" << kThree << "' title '3-ipp, unstable', "
       << "'' using 1:($5 == 1 && $6 == 1 ? $4 : 1/0) with lines lw 3 lc rgb '" << kThree << "' title '3-ipp, stable', "
       << "'fig16_one_impact.csv' using 1:($3 == 1 ? $2 : 1/0) with points pt 7 ps 0.35 lc rgb '" << kOneStable
       << "' title '1-ipp, stable', "
       << "'' using 1:($3 == 0 ? $2 : 1/0) with points pt 7 ps 0.35 lc rgb '" << kOneUnstable
       << "' title '1-ipp, unstable'\n"
       << "unset arrow\nunset logscale y\nset autoscale y\nset xrange [0:" << pick.start.period << "]\n"
       << "set xlabel 'time t (s)'\nset ylabel '" << XcLabel(c) << "'\n"
       << "plot 'fig16_orbit.csv' using " << TCol() << ":" << XCol(c, c.contact)
       << " with lines lw 2 lc rgb '" << kThree << "' title 'x_c(t), T = " << period_label.str() << "', " << c.b.gap << " with lines dt 2 lc rgb 'black' title 'obstacle d'\n"
       << "unset multiplot";
  out.Commit();
  one.Commit();
  orbit.Commit();
  Draw(c, "fig16_three_impact_family", body.str());
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
         << "set title 'work-precision: " << name << "'\nset key outside right\nset grid\n"
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
