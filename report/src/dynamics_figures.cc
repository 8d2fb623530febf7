// The pictures the dynamics needs, beside the paper's figures (issue 28):
// the model drawn (the paper's Fig. 1), the Floquet multipliers along the
// 1-impact branch, a time history with its velocity jumps, analytic orbits
// against their simulations, the frequency-energy plot with the 3-impact
// family, and a bar's contact in space and time. Each is DIR/NAME.{csv,png,
// svg,pdf,column.pdf} (+ scripts), drawn by role (report/style.toml).
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <numbers>
#include <sstream>

#include "chart.h"
#include "nsmodal/figure_subjects.h"
#include "nsmodal/flow.h"
#include "nsmodal/figures.h"
#include "nsmodal/gnuplot.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/simulate.h"
#include "nsmodal/trajectory.h"
#include "nsmodal/validate.h"

namespace nsmodal::report {
namespace {

// The spring of a drawing: a zigzag from (x0, y) to (x1, y), flat ends, to
// the datablock `os` (one block).
void Zigzag(std::ostream& os, double x0, double x1, double y) {
  const int teeth = 6;
  const double lead = 0.15 * (x1 - x0), w = (x1 - x0 - 2 * lead) / (2 * teeth), h = 0.18;
  os << x0 << "," << y << "\n" << x0 + lead << "," << y << "\n";
  for (int k = 0; k < 2 * teeth; ++k) os << x0 + lead + (k + 0.5) * w << "," << y + (k % 2 ? -h : h) << "\n";
  os << x1 - lead << "," << y << "\n" << x1 << "," << y << "\n\n";
}

// A rigid wall at x from y0 to y1, hatched on the side `side` (-1 left, +1 right).
void Wall(std::ostream& os, double x, double y0, double y1, int side) {
  os << x << "," << y0 << "\n" << x << "," << y1 << "\n\n";
  for (double y = y0; y < y1 - 1e-9; y += 0.2) os << x << "," << y << "\n" << x + side * 0.2 << "," << y + 0.2 << "\n\n";
}

// The first stable admissible 1-ipp orbit of the sweep, at the middle of its
// stable stretch (the orbit of the time history and of the validation).
std::optional<Orbit> StableOneImpact(const Context& c) {
  const auto& at = c.atlas.one.at;
  for (std::size_t k = 0; k < at.size(); ++k) {
    if (!at[k].front().orbit.admissible || !IsStable(at[k].front().stability)) continue;
    std::size_t end = k;
    while (end + 1 < at.size() && at[end + 1].front().orbit.admissible && IsStable(at[end + 1].front().stability)) ++end;
    return at[(k + end) / 2].front().orbit;
  }
  return std::nullopt;
}

// The stable admissible 2-ipp orbit off t2 = T/2 of the sweep with the
// lowest energy (an orbit the 1-ipp family does not hold, of the size of
// the obstacle's distance rather than near a singular transition).
std::optional<Orbit> StableTwoImpact(const Context& c) {
  std::optional<Orbit> best;
  for (const auto& list : c.atlas.two.at) {
    for (const OrbitRecord& r : list) {
      if (r.orbit.admissible && IsStable(r.stability) && !IsHalfPeriodRoot(r.orbit) &&
          (!best || r.orbit.energy < best->energy)) {
        best = r.orbit;
      }
    }
  }
  return best;
}

}  // namespace

// fig01_model: the paper's Fig. 1 for any chain of masses and springs (M
// diagonal, K tridiagonal): a wall, the springs to the ground and between
// the masses, the masses with their displacements, the stop at distance d.
void FigureModel(Context& c) {
  if (!c.model) return;
  const Model& m = *c.model;
  const int n = m.dofs();
  bool chain = m.mass.isDiagonal();
  for (int i = 0; i < n && chain; ++i) {
    for (int j = i + 2; j < n; ++j) chain = chain && m.stiffness(i, j) == 0.0;
  }
  const Contact& stop = m.FirstContact();
  if (!chain || n > 8 || stop.form != Contact::Form::kDof || !stop.upper || stop.dof != n - 1) {
    c.log << "  fig01_model: drawn for chains of up to 8 masses with the stop beyond the last one; skipped\n";
    return;
  }
  // Spring to the ground of dof i: the row sum of K; between i and i + 1: -K(i, i+1).
  std::ostringstream lines, body;
  const double pitch = 3.0, size = 1.0;
  auto left = [&](int i) { return 2.0 + pitch * i; };
  lines << "$drawing << EOD\n";
  Wall(lines, 0.0, -0.3, 1.3, -1);
  for (int i = 0; i < n; ++i) {
    const double ground = m.stiffness.row(i).sum();
    const std::string mass = "m_{" + std::to_string(i + 1) + "} = " + Num(m.mass(i, i)) + " kg";
    body << "set object " << i + 1 << " rect from " << left(i) << ",0 to " << left(i) + size << "," << size
         << " fc rgb '" << style::Colour("fill") << "' fs solid 1 border lc rgb '" << style::Colour("black") << "' lw 1.5\n"
         << "set label '" << mass << "' at " << left(i) + 0.5 * size << ", -0.35 center\n"
         << "set arrow from " << left(i) + 0.5 * size << ", 1.35 to " << left(i) + 0.5 * size + 0.8 << ", 1.35 head size 0.12,25 "
         << style::Look("function") << "\nset label 'x_{" << i + 1 << "}' at " << left(i) + 0.5 * size + 0.4 << ", 1.6 center\n";
    // (The displacement's origin: a short datum line at the arrow's tail,
    // over the mass's middle at rest.)
    lines << left(i) + 0.5 * size << ",1.22\n" << left(i) + 0.5 * size << ",1.48\n\n";
    if (i == 0) {
      if (!(ground > 1e-12 * m.stiffness.norm())) {
        c.log << "  fig01_model: mass 1 has no spring to the wall: drawn for chains fixed at the left; skipped\n";
        return;
      }
      Zigzag(lines, 0.0, left(0), 0.5);
      body << "set label 'k_{1} = " << Num(ground) << " N/m' at " << 0.5 * left(0) << ", 0.95 center\n";
    } else if (ground > 1e-12 * m.stiffness.norm()) {
      c.log << "  fig01_model: dof " << i + 1 << " has a spring to the ground: drawn for chains fixed at the left; skipped\n";
      return;
    }
    if (i + 1 < n) {
      Zigzag(lines, left(i) + size, left(i + 1), 0.5);
      body << "set label 'k_{" << i + 2 << "} = " << Num(-m.stiffness(i, i + 1)) << " N/m' at "
           << 0.5 * (left(i) + size + left(i + 1)) << ", 0.95 center\n";
    }
  }
  // The gap 1.5 wide (at 1, "d = 1 m" filled it, 1 px from the wall in the
  // column PDF), its arrow across it at the mass's middle, from its face to
  // the wall (under the mass, its end hung over "m = 1 kg"), "d" above the
  // arrow, in the gap, as the caption says.
  const double wall = left(n - 1) + size + 1.5;
  Wall(lines, wall, -0.3, 1.3, 1);
  lines << "EOD\n";
  body << "set arrow from " << left(n - 1) + size << ", 0.5 to " << wall << ", 0.5 heads size 0.1,25 "
       << style::Look("function") << "\nset label 'd = " << Num(m.FirstContact().gap) << " m' at "
       << 0.5 * (left(n - 1) + size + wall) << ", 0.78 center\n"
       << "set label 'e = " << Num(stop.restitution) << "' at " << wall << ", 1.6 center\n";
  std::ostringstream chart;
  // The canvas of the drawing's shape: no white bands around it.
  // (From under the masses' labels to over x_i's: the PNG had bands of a
  // fifth of its height above and below.)
  const double x_lo = -0.6, x_hi = wall + 0.8, y_lo = -0.62, y_hi = 1.85;
  chart << "unset border\nunset tics\nunset grid\nunset key\nset size ratio -1\nset margins 0, 0, 0, 0\nset xrange ["
        << x_lo << ":" << x_hi << "]\nset yrange [" << y_lo << ":" << y_hi << "]\n" << lines.str() << body.str();
  Plot plot;
  plot.Unkeyed("$drawing using 1:2", With("function"));
  report::ResultFile out(c.dir, "fig01_model.csv");
  out << "dof,mass,spring_to_left\n";
  for (int i = 0; i < n; ++i) {
    out << i + 1 << "," << m.mass(i, i) << "," << (i == 0 ? m.stiffness.row(0).sum() : -m.stiffness(i - 1, i)) << "\n";
  }
  out.Commit();
  Draw(c, "fig01_model", chart.str() + plot.str(), std::to_string(n) + " masses, the stop beyond mass " + std::to_string(n),
       (y_hi - y_lo) / (x_hi - x_lo));
}

// multipliers_one_impact: the Floquet multipliers of the admissible 1-ipp
// orbits along the branch. Above: the largest modulus against T (solid where
// the orbit is stable, dashed where not), |mu| = 1 and the stability changes
// marked. Below: every multiplier in the complex plane with the unit circle,
// shaded by the orbit's position along the branch.
void FigureMultipliers(Context& c) {
  report::ResultFile out(c.dir, "multipliers_one_impact.csv");
  out << "T,stable,max_modulus,k,re,im,index_in_stability\n";
  long stable = 0, unstable = 0, points = 0;
  double t_lo = INFINITY, t_hi = -INFINITY, m_hi = 1.0;
  int last = -2;
  // The branch's widest gap in T (where it is not admissible): the key's place.
  double prev_period = NAN, gap_lo = NAN, gap_hi = NAN;
  // The branch's largest modulus, one row per orbit (T, stable, max |mu|),
  // a blank line at each gap: the upper panel's lines.
  std::ostringstream branch;
  branch << "$branch << EOD\n";
  for (std::size_t k = 0; k < c.atlas.one.at.size(); ++k) {
    const OrbitRecord& r = c.atlas.one.at[k].front();
    if (!r.orbit.admissible || !r.stability || r.stability->multipliers.size() == 0) continue;
    if (last >= 0 && static_cast<int>(k) != last + 1) {  // a gap in the branch breaks its line
      out << "\n";
      branch << "\n";
      if (!(r.orbit.period - prev_period <= gap_hi - gap_lo)) {
        gap_lo = prev_period;
        gap_hi = r.orbit.period;
      }
    }
    last = static_cast<int>(k);
    prev_period = r.orbit.period;
    const Stability& s = *r.stability;
    branch << r.orbit.period << "," << s.stable << "," << s.max_modulus << "\n";
    (s.stable ? stable : unstable) += 1;
    t_lo = std::min(t_lo, r.orbit.period);
    t_hi = std::max(t_hi, r.orbit.period);
    m_hi = std::max(m_hi, s.max_modulus);
    for (long j = 0; j < s.multipliers.size(); ++j) {
      out << r.orbit.period << "," << s.stable << "," << s.max_modulus << "," << j << "," << s.multipliers[j].real() << ","
          << s.multipliers[j].imag() << "," << (s.stable ? stable : unstable) - 1 << "\n";
      ++points;
    }
  }
  out.Commit();
  if (points == 0) {
    c.log << "  multipliers_one_impact: no admissible 1-ipp orbit with its multipliers; skipped\n";
    return;
  }
  // The changes of stability marked in a row under |mu| = 1, where no
  // branch runs (max |mu| >= 1: the multipliers of a conservative orbit come
  // in pairs mu, 1/mu), each pointing at its place: on the line, the
  // triangles hid the short stable stretches they bound (0.6 s wide at
  // T = 5). A mark within 1.5 % of the period range of the one before it
  // (of either kind) goes one row further down (the two -1 triangles at
  // T = 9.49 and 9.62 lay over each other). The row named "crossings" in
  // its widest gap, where that is a sixth of the range or more (a reader
  // took a triangle for a value of max |mu| under 1).
  constexpr double kRow = 1.3;  // a row's step down from |mu| = 1 (a factor: the axis is logarithmic)
  std::vector<std::pair<double, bool>> crossings;  // (T, through +1)
  for (const Transition& t : c.transitions) {
    if (t.kind == TransitionKind::kMultiplierPlusOne) crossings.push_back({t.period, true});
    if (t.kind == TransitionKind::kMultiplierMinusOne) crossings.push_back({t.period, false});
  }
  std::sort(crossings.begin(), crossings.end());
  const long plus = std::count_if(crossings.begin(), crossings.end(), [](const auto& x) { return x.second; });
  const long minus = static_cast<long>(crossings.size()) - plus;
  int rows = 1;
  std::vector<int> row(crossings.size(), 1);
  for (std::size_t k = 1; k < crossings.size(); ++k) {
    if (crossings[k].first - crossings[k - 1].first < 0.015 * (t_hi - t_lo)) row[k] = row[k - 1] + 1;
    rows = std::max(rows, row[k]);
  }
  std::ostringstream marks;
  for (const bool through_plus : {true, false}) {
    marks << (through_plus ? branch.str() + "EOD\n$plus << EOD\n" : "EOD\n$minus << EOD\n");
    for (std::size_t k = 0; k < crossings.size(); ++k) {
      if (crossings[k].second == through_plus) marks << crossings[k].first << "," << std::pow(kRow, -row[k]) << "\n";
    }
  }
  std::string crossings_label;
  if (!crossings.empty()) {
    const double x_lo = t_lo - 0.02 * (t_hi - t_lo), x_hi = t_hi + 0.02 * (t_hi - t_lo);
    double gap_from = x_lo, gap = crossings.front().first - x_lo;
    for (std::size_t k = 0; k < crossings.size(); ++k) {
      const double next = k + 1 < crossings.size() ? crossings[k + 1].first : x_hi;
      if (next - crossings[k].first > gap) {
        gap = next - crossings[k].first;
        gap_from = crossings[k].first;
      }
    }
    if (gap >= (x_hi - x_lo) / 6.0) {
      std::ostringstream os;
      os << "set label 'crossings' at " << gap_from + 0.5 * gap << ", " << std::pow(kRow, -1.0) << " center\n";
      crossings_label = os.str();
    }
  }
  marks << "EOD\n$circle << EOD\n";
  for (int k = 0; k <= 180; ++k) marks << std::cos(k * std::numbers::pi / 90) << "," << std::sin(k * std::numbers::pi / 90) << "\n";
  marks << "EOD\n";
  const double m_top = std::min(m_hi, 1e3) * 1.5, m_bottom = std::pow(kRow, -(rows + 1.4));
  std::ostringstream body;
  // Two panels stacked (height 1.15 width), their frames between the same
  // left and right edges: above, the branch, where the stability changes
  // 1.1 apart in T stand apart even in a journal's column, one key for both
  // inside it, over the widest stretch where the branch is not admissible
  // (T 10-19, clear of the spike at 20.4); below, the complex plane at equal scales, its colour bar
  // beside it in the upper panel's right margin.
  // (The complex plane's Im within 1.5 of 0: beyond 1, nothing, and at 1.4
  // the frame's Re range, 2.37, put the multiplier at 2.35 on its edge; the
  // rest of the height to the branch. kBottom: room for "Re mu" in the
  // column PDF.)
  // (kLeft: room for "1000" and the label in the column PDF; at 0.11 the
  // label touched the page's edge.)
  constexpr double kLeft = 0.13, kRight = 0.81, kBottom = 0.085, kTop = 0.42, kAspect = 1.15, kIm = 1.5;
  body << marks.str() << "set multiplot\nset size 1, 0.53\nset origin 0, 0.47\n" << crossings_label
       << "set lmargin at screen " << kLeft << "\nset rmargin at screen " << kRight << "\n"
       // (Centred on the branch's widest gap: from its left end at graph
       // 0.29, the column PDF's wider key covered the spike at T = 20.4.)
       << "set key at " << (std::isfinite(gap_lo) ? 0.5 * (gap_lo + gap_hi) : 0.5 * (t_lo + t_hi))
       << ", graph 0.97 center top Left reverse samplen 1.5 maxrows 7\n"
       << "set xlabel 'period T (s)'\n"
       // (From a row under the marks' last row and 2 % beyond the
       // branch's ends: the marks and the ends' points clear of the frame.)
       << "set ylabel 'max |{/Symbol m}|'\nset logscale y\n" << LogTics("y", m_bottom, m_top) << "set yrange ["
       << m_bottom << ":" << m_top << "]\n"
       << "set xrange [" << t_lo - 0.02 * (t_hi - t_lo) << ":" << t_hi + 0.02 * (t_hi - t_lo) << "]\n";
  // |mu| = 1 first: the stable stretches lie on it, a thick solid line over
  // its thin dashes; the unstable ones dashed, as on Fig. 3, over their
  // path drawn thin and solid (the spikes are a few samples wide: the
  // dashes' gaps cut 187 to 165 at T = 8.9).
  Plot left;
  left.Add("1", With("unit_circle"), "|{/Symbol m}| = 1")
      .Add("$branch using 1:($2 == 1 ? $3 : 1/0)", With("one_stable"), "stable", stable)
      .Unkeyed("$branch using 1:($2 == 0 ? $3 : 1/0)", With("one_unstable_trace"))
      .Add("$branch using 1:($2 == 0 ? $3 : 1/0)", With("one_unstable"), "unstable", unstable)
      .Add("$plus using 1:2", With("multiplier_plus_one"), "{/Symbol m} through +1", plus)
      .Add("$minus using 1:2", With("multiplier_minus_one"), "{/Symbol m} through -1", minus);
  // The complex plane: Im mu within 1.5 of 0 and Re mu as far as the frame's
  // width allows at equal scales (the larger real ones of the unstable orbits
  // are on the upper panel), of every third stable and every third unstable
  // orbit (all of them lay hundreds deep: filled and open could not be told;
  // counted apart, a short stable stretch keeps its points).
  const double re_half = kIm * (kRight - kLeft) / ((kTop - kBottom) * kAspect);
  // (The lower panel's two keys in a row over its unit circle, where Im mu
  // > 1 holds nothing: in the upper key, they made it wider than the gap it
  // stands in, and in the column PDF it covered the spikes at T = 8.9 and
  // 20.4.)
  body << left.str() << "unset logscale y\nunset label\nset size 1, 0.47\nset origin 0, 0\n"
       << "set key at graph 0.02, graph 0.985 left top Left reverse horizontal samplen 1 maxrows 1\n"
       << "set bmargin at screen " << kBottom << "\nset tmargin at screen " << kTop << "\n"
       << "set colorbox user origin screen " << kRight + 0.02 << ", screen " << kBottom << " size screen 0.022, screen "
       << kTop - kBottom << "\n"
       << "set xrange [" << -re_half << ":" << re_half << "]\nset yrange [" << -kIm << ":" << kIm << "]\nset xtics 1\nset ytics 1\n"
       << "set xlabel 'Re {/Symbol m}'\nset ylabel 'Im {/Symbol m}'\n"
       << style::Palette("family", "T (s) along the 1-ipp branch") << FamilyBarTics(t_lo, t_hi) << "set cbrange [0:1]\n";
  // The multipliers of the unstable orbits open, of the stable ones filled
  // over them; the unit circle over the points (the line |mu| = 1 of the
  // upper panel).
  const std::string shade = ":(($1 - " + std::to_string(t_lo) + ") / " + std::to_string(std::max(t_hi - t_lo, 1e-300)) + ")";
  const std::string third = "(floor($7 / 3) * 3 == $7 && ";
  Plot right;
  right.Add("'multipliers_one_impact.csv' using (" + third + "$2 == 0) ? $5 : 1/0):6" + shade,
            style::WithPalette("map_unstable"), "", unstable)
      .Add("'' using (" + third + "$2 == 1) ? $5 : 1/0):6" + shade, style::WithPalette("map_stable"), "", stable)
      .Add("$circle using 1:2", With("unit_circle"), "", 1);  // keyed with |mu| = 1
  // (Legend-only, in black: their colour is T's.)
  if (stable > 0) right.KeyOnly(With("map_stable", "points", style::Colour("black")), "{/Symbol m}, stable orbit");
  if (unstable > 0) right.KeyOnly(With("map_unstable", "points", style::Colour("black")), "{/Symbol m}, unstable orbit");
  body << right.str() << "unset multiplot";
  Draw(c, "multipliers_one_impact", body.str(),
       std::to_string(stable + unstable) + " admissible orbits, T from " + Num(t_lo) + " to " + Num(t_hi) +
           ", largest |mu| " + Num(m_hi),
       kAspect);
}

// time_history: x and v of the contact dof (and x of the others) over three
// periods of the stable 1-ipp orbit, simulated by the exact integrator from
// the orbit's state at T/2, the velocity jumps at the impacts drawn as
// segments.
void FigureTimeHistory(Context& c) {
  const std::optional<Orbit> o = StableOneImpact(c);
  if (!c.model || !o) {
    c.log << "  time_history: no stable admissible 1-ipp orbit in the sweep; skipped\n";
    return;
  }
  const int n = c.b.n, periods = 3;
  SimulateOptions opt;
  opt.t_end = periods * o->period;
  opt.sample_dt = o->period / kSamples;
  report::ResultFile out(c.dir, "time_history.csv");
  report::ResultFile jumps(c.dir, "time_history_impacts.csv");
  out << "t";
  for (int i = 1; i <= n; ++i) out << ",x" << i;
  for (int i = 1; i <= n; ++i) out << ",v" << i;
  out << "\n";
  jumps << "t,x_c,v_before,v_after\n";
  double v_lo = 0.0, v_hi = 0.0;  // the contact velocity's range (about four ticks on it)
  double x_lo = c.b.gap, x_hi = c.b.gap;  // the displacements' and d's (the same)
  auto row = [&](double t, const Eigen::VectorXd& z) {
    x_lo = std::min(x_lo, z.head(n).minCoeff());
    x_hi = std::max(x_hi, z.head(n).maxCoeff());
    v_lo = std::min(v_lo, z[n + c.contact]);
    v_hi = std::max(v_hi, z[n + c.contact]);
    out << t;
    for (long k = 0; k < z.size(); ++k) out << "," << z[k];
    out << "\n";
  };
  SimulationObserver observer;
  observer.on_sample = row;
  // The state just before and just after each impact, a line break between:
  // the jump is a segment of its own, not a slope of the samples.
  observer.on_impact = [&](const ContactEvent& e) {
    row(e.t, e.before);
    out << "\n";
    row(e.t, e.after);
    jumps << e.t << "," << e.before[c.contact] << "," << e.before[n + c.contact] << "," << e.after[n + c.contact] << "\n";
  };
  // Started half a period after an impact: the three impacts fall inside.
  Eigen::VectorXd y = o->y0;
  Flow(c.b, 0.5 * o->period, y);
  const Eigen::VectorXd z = PhysicalOf(c.b, y);
  const SimulationSummary s = Simulate(*c.model, z.head(n), z.tail(n), opt, observer);
  out.Commit();
  jumps.Commit();
  std::ostringstream body;
  const std::string t = "1", xc = std::to_string(2 + c.contact), vc = std::to_string(2 + n + c.contact);
  // Two panels of one height placed by hand over one key for both, at the
  // foot of the canvas, spaced for the subscripts. (Each panel's own key
  // below it took the displacement panel's height in the column PDF.) The
  // orbit's period in the impacts' entry, as Figs. 2, 5 and 9 give it in
  // their keys (charts carry no title; in the contact's entry, the key took
  // one column in the column PDF).
  // (Their foot over the x label and the key's band, 0.14 of the height
  // where the key has the column PDF's rows: KeyFoot.)
  const std::string foot = KeyFoot(0.12, 0.14);
  auto panel = [](const std::string& bottom, const std::string& top) {
    std::ostringstream os;
    os << "set lmargin at screen 0.14\nset rmargin at screen 0.96\nset bmargin at screen " << bottom
       << "\nset tmargin at screen " << top << "\n";
    return os.str();
  };
  std::ostringstream upper_foot, lower_top;
  upper_foot << "((" << foot << " + 0.96) / 2 + 0.01)";
  lower_top << "((" << foot << " + 0.96) / 2 - 0.01)";
  body << "set multiplot\nset xrange [0:" << opt.t_end << "]\nset format x ''\n"
       // (The two axes' titles at one place on the canvas, the middle of
       // their panels: as ylabels, "d = 1" pushed the upper one left of the
       // lower.)
       << panel(upper_foot.str(), "0.96") << "set ylabel ''\nset label 91 'displacement (m)' at screen 0.035, screen ("
       << upper_foot.str() << " + 0.96) / 2 center rotate by 90\nset ytics " << NiceStep(x_lo, x_hi, 4) << "\n"
       // (d named on the axis with its value: the round ticks stopped short
       // of it, and "d" alone never said it was 1.)
       << "set ytics add ('d = " << Num(c.b.gap) << "' " << c.b.gap << ")\n"
       // (Its range the motion's, not the tics': rounded out, -6 to 2 left a
       // fifth of the panel empty.)
       << "set yrange [" << x_lo - 0.06 * (x_hi - x_lo) << ":" << x_hi + 0.06 * (x_hi - x_lo) << "]\n";
  const std::string contact = std::to_string(c.contact + 1);
  Plot top("plot", Plot::Keys::kCollected);
  const std::string contact_title = "x_{" + contact + "}, v_{" + contact + "} (contact)";
  top.Add("'time_history.csv' using " + t + ":" + xc, With("dof_contact"), contact_title);
  for (int i = 0; i < n; ++i) {
    if (i == c.contact) continue;
    if (i == (c.contact == 0 ? 1 : 0)) {
      top.Add("'time_history.csv' using 1:" + std::to_string(2 + i), With("dof_other"),
              n == 2 ? "x_{" + std::to_string(i + 1) + "}" : std::string("the other masses' x"));
    } else {
      top.Unkeyed("'time_history.csv' using 1:" + std::to_string(2 + i), With("dof_other"));
    }
  }
  top.Add(std::to_string(c.b.gap), With("obstacle"), "obstacle d")
      .Add("'time_history_impacts.csv' using 1:2", With("orbit_impact"), "impacts, every T = " + Num(o->period) + " s",
           s.impacts);
  Plot bottom("plot", Plot::Keys::kCollected);
  bottom.Add("'time_history.csv' using 1:" + vc, With("dof_contact"), contact_title)
      .Add("'time_history_impacts.csv' using 1:3:(0):($4 - $3)", With("velocity_jump"), "velocity jump at an impact",
           s.impacts);
  std::vector<Plot::Entry> entries = top.Collected();
  entries.insert(entries.end(), bottom.Collected().begin(), bottom.Collected().end());
  body << top.str() << "set format x '% g'\nset xlabel 'time t (s)'\nunset label 91\nset label 92 'contact velocity (m/s)' at "
       << "screen 0.035, screen (" << foot << " + " << lower_top.str() << ") / 2 center rotate by 90\nset yrange [*:*]\n"
       << panel(foot, lower_top.str()) << "set ytics " << NiceStep(v_lo, v_hi, 6) << "\n" << bottom.str()
       << LegendPanel(0.14)
       << "set key spacing 1.3\n" << Plot::Legend(entries) << "unset multiplot";
  Draw(c, "time_history", body.str(),
       "the stable 1-ipp orbit T = " + Num(o->period, 6) + ", " + std::to_string(periods) + " periods simulated (exact), " +
           std::to_string(s.impacts) + " impacts");
}

// validation_orbits: analytic orbits against their simulations. Top row:
// x_c over one period of each orbit (line) and the exact integrator's
// samples over its 100th period (points, shifted back by 99 T). Bottom row:
// the deviation from the analytic state after each of 1,000 periods.
void FigureValidation(Context& c, const ThreeImpactPick& three) {
  if (!c.model) return;
  std::vector<std::pair<std::string, Orbit>> orbits;
  if (const auto o = StableOneImpact(c)) orbits.emplace_back("1-ipp", *o);
  if (const auto o = StableTwoImpact(c)) orbits.emplace_back("2-ipp", *o);
  for (const Orbit& o : three.family) {
    if (o.admissible && OrbitStability(c.b, o).stable) {
      orbits.emplace_back("3-ipp", o);
      break;
    }
  }
  if (orbits.empty()) {
    c.log << "  validation_orbits: no stable admissible orbit in the sweep; skipped\n";
    return;
  }
  const int n = c.b.n, shown = 100;
  ValidateOptions vopt;
  vopt.periods = 1000;
  report::ResultFile out(c.dir, "validation_orbits.csv");
  report::ResultFile dev(c.dir, "validation_deviation.csv");
  out << "orbit,source,phase,x_c\n";
  dev << "orbit,period,deviation\n";
  std::ostringstream note, body;
  double dev_lo = INFINITY, dev_hi = 0.0;
  std::vector<std::pair<double, double>> x_range;
  for (std::size_t k = 0; k < orbits.size(); ++k) {
    const std::string& label = orbits[k].first;
    const Orbit& o = orbits[k].second;  // (not a structured binding: the lambda below captures it)
    const Eigen::MatrixXd tr = OrbitTrajectory(c.b, o, kSamples);
    x_range.emplace_back(tr.col(1 + c.contact).minCoeff(), tr.col(1 + c.contact).maxCoeff());
    for (long r = 0; r < tr.rows(); ++r) out << k << ",analytic," << tr(r, 0) / o.period << "," << tr(r, 1 + c.contact) << "\n";
    SimulateOptions sopt;
    sopt.t_end = shown * o.period;
    // (16 samples a period: at 40, and still at 24, their circles hid the
    // analytic line and its family colour; each in the middle of its
    // sixteenth, off t = 0 and T, where the impact dots are: at j / 16 one
    // fell on the 2-ipp orbit's impact at t2 / T = 0.69.)
    for (int j = 0; j < 16; ++j) sopt.sample_times.push_back((shown - 1 + (j + 0.5) / 16.0) * o.period);
    SimulationObserver observer;
    observer.on_sample = [&](double t, const Eigen::VectorXd& z) {
      out << k << ",simulated," << t / o.period - (shown - 1) << "," << z[c.contact] << "\n";
    };
    Simulate(*c.model, o.z0.head(n), o.z0.tail(n), sopt, observer);
    const OrbitValidation v = ValidateOrbit(*c.model, o, Integrator::kExact, vopt);
    double worst = 0.0;
    for (std::size_t p = 0; p < v.deviation.size(); ++p) {
      dev << k << "," << p + 1 << "," << v.deviation[p] << "\n";
      worst = std::max(worst, v.deviation[p]);
      if (v.deviation[p] > 0.0) dev_lo = std::min(dev_lo, v.deviation[p]);
    }
    dev << "\n\n";
    dev_hi = std::max(dev_hi, worst);
    note << (k ? "; " : "") << label << " T = " << Num(o.period, 6) << ": max deviation " << Num(worst, 2) << " over "
         << v.deviation.size() << " periods";
  }
  out.Commit();
  dev.Commit();
  const int cols = static_cast<int>(orbits.size());
  // Panels placed by hand (margins and gaps wide enough for the column
  // PDF's tick labels) over one key for all, at the foot of the canvas as
  // wide as the canvas: the panels draw the same series. (Their foot over
  // the x labels and the key's band, 0.14 of the height where the key has
  // the column PDF's rows: KeyFoot; ns_h, a row's height.)
  auto panel = [&](int row, int col) {
    constexpr double kLeft = 0.14, kRight = 0.96, kTop = 0.9, kGapX = 0.09, kGapY = 0.14;
    const double w = (kRight - kLeft - (cols - 1) * kGapX) / cols;
    const double x0 = kLeft + col * (w + kGapX);
    std::ostringstream os;
    os << "set lmargin at screen " << x0 << "\nset rmargin at screen " << x0 + w << "\nset bmargin at screen ("
       << kTop << " - " << row + 1 << " * ns_h - " << row * kGapY << ")\nset tmargin at screen (" << kTop << " - " << row
       << " * ns_h - " << row * kGapY << ")\n";
    return os.str();
  };
  // (Each panel's x_c range its orbit's: ContactTimeRange.)
  body << "set multiplot\nns_h = (0.9 - " << KeyFoot(0.11, 0.14) << " - 0.14) / 2.0\n";
  std::vector<Plot::Entry> entries;
  for (int k = 0; k < cols; ++k) {
    const Orbit& o = orbits[k].second;
    const auto [x_lo, x_hi] = x_range[k];
    body << panel(0, k) << "set title '" << orbits[k].first << ", T = " << Num(o.period) << "'\nset xlabel 't / T'\nset ylabel '"
         << (k == 0 ? DofLabel("x", c.contact, "m") : std::string()) << "'\nset xrange [0:1]\nset xtics 0.5\nset ytics "
         << NiceStep(x_lo, std::max(x_hi, c.b.gap), 5) << "\n" << ContactTimeRange(c, x_lo, x_hi);
    Plot p("plot", Plot::Keys::kCollected);
    // Each orbit in its family's colour (Fig. 8's), keyed once in black.
    const char* family = o.impacts == 1 ? "one_stable" : o.impacts == 2 ? "two_stable" : "three_stable";
    if (k == 0) p.KeyOnly(With("analytic", "lines", style::Colour("black")), "analytic (in the family colour)");
    p.Unkeyed("'validation_orbits.csv' using ($1 == " + std::to_string(k) + " && strcol(2) eq 'analytic' ? $3 : 1/0):4",
              With("analytic", "lines", style::RoleColour(family)))
        .Add("'' using ($1 == " + std::to_string(k) + " && strcol(2) eq 'simulated' ? $3 : 1/0):4", With("simulated"),
             "simulated, " + std::to_string(shown) + "th period")
        .Add(std::to_string(c.b.gap), With("obstacle"), "obstacle d");
    // Its impacts: t = 0 (and T) and each further one, on t / T.
    std::vector<double> impacts = {0.0, 1.0};
    for (const double t : o.times) impacts.push_back(t / o.period);
    ImpactMarks(c, impacts)(p);
    entries.insert(entries.end(), p.Collected().begin(), p.Collected().end());
    body << p.str();
  }
  // The deviations on one scale, the panels compared at a glance.
  const double decade_lo = std::floor(std::log10(std::isfinite(dev_lo) ? dev_lo : 1e-16));
  const double decade_hi = std::ceil(std::log10(dev_hi > 0.0 ? dev_hi : 1e-15));
  // (A label every few decades, at most 4 labels, a tick at each decade.)
  const double per_label = std::max(1.0, std::ceil((decade_hi - decade_lo) / 4));
  body << "unset title\nset logscale y\nset format y '10^{%T}'\nset yrange [1e" << decade_lo << ":1e" << decade_hi
       << "]\nset ytics " << std::pow(10.0, per_label) << "\nset xrange [0:"
       << vopt.periods << "]\nset xtics 0, " << vopt.periods / 2 << ", " << vopt.periods
       << "\nset mxtics 2\nset mytics " << per_label << "\nset xlabel 'periods k'\n";
  for (int k = 0; k < cols; ++k) {
    // One scale: its tick labels on the first panel only.
    // (Short labels: the long ones overhung their panels in the column PDF;
    // the caption names them.)
    body << panel(1, k) << "set ylabel '" << (k == 0 ? "|{/Symbol D}z| / |z_0|" : "") << "'\n"
         << (k == 1 ? "set format y ''\n" : "");
    Plot p;
    p.Unkeyed("'validation_deviation.csv' index " + std::to_string(k) + " using 2:($3 > 0 ? $3 : 1/0)", With("function"));
    body << p.str();
  }
  // (The key's band below the x labels: 0.07 ran into them in the column.)
  body << LegendPanel(0.11) << Plot::Legend(entries) << "unset multiplot";
  Draw(c, "validation_orbits", body.str(), note.str());
}

// fep_all_families: the frequency-energy plot of Fig. 8 with the 3-ipp
// family of Fig. 16 (its admissible orbits), the bridges and transitions.
void FigureAllFamilies(Context& c, const ThreeImpactPick& three) {
  FepTable table;
  table.AddAtlas(c.atlas);
  std::vector<Orbit> drawn;
  // The family's stable stretches, each as its first and last period.
  StableStretches stretches;
  int last_step = 0;
  std::optional<Stability> last_stability;
  for (std::size_t k = 0; k < three.family.size(); ++k) {
    const Orbit& o = three.family[k];
    const std::optional<Stability> s = o.admissible ? std::optional<Stability>(OrbitStability(c.b, o)) : std::nullopt;
    if (o.admissible) {
      table.Add(static_cast<int>(k), o, s);
      drawn.push_back(o);
      last_step = static_cast<int>(k);
      last_stability = s;
    }
    stretches.Add(o.period, o.admissible && IsStable(s));
  }
  // The family drawn to its end on a 1-ipp grazing orbit (as the 1-ipp
  // stretches are drawn to theirs: on paper.toml its last orbit of the grid,
  // T = 29.30, stopped 0.007 s short of B3's top at T_G = 29.3072): where
  // the last admissible orbit lies within a step of the admissible stretch's
  // end and within 2 % of that grazing orbit's energy, the grazing orbit
  // ends the line, with the last orbit's stability.
  if (!drawn.empty()) {
    const Orbit& last = drawn.back();
    const Orbit graze = OneImpactOrbit(c.b, three.admissible_to);
    const double gap = three.admissible_to - last.period;
    if (gap > 0.0 && gap <= 0.011 && std::abs(graze.energy - last.energy) <= 0.02 * graze.energy) {
      Orbit end = last;
      end.period = three.admissible_to;
      end.energy = graze.energy;
      table.Add(last_step, end, last_stability);  // (the same step: the stretch's end)
      drawn.push_back(end);
    }
  }
  // A stable stretch too short to see (under 1 % of the period axis; on
  // paper.toml two orbits, T = 28.85 and 28.86, at the family's lowest
  // energy) zoomed on, labelled: its key entry had nothing to show.
  // (The window at least 0.3 % of the axis wide, not the 1 % of the 1-ipp
  // chart's: there the stretch was two dots on each other.)
  const double axis = PeriodTop(c, false);
  std::vector<Zoom> zooms;
  for (const auto& [first, last] : stretches.stretches()) {
    if (last - first > 0.01 * axis) continue;
    const auto [w_lo, w_hi] = StretchWindow(first, last, axis, 0.0015);
    const auto [e_lo, e_hi] = EnergySpan(drawn, w_lo, w_hi);
    if (!(e_hi > e_lo)) continue;
    const double pad = 0.2 * (e_hi - e_lo);
    Zoom z{w_lo, w_hi, e_lo - pad, e_hi + pad, "3-ipp, stable"};
    z.label_centred = true;  // (the family's arms rise to the window's top corners)
    zooms.push_back(z);
  }
  const std::string body = FepChart(c, table, "fep_all_families.csv", "fep_all_families_bridges.csv",
                                    "fep_all_families_transitions.csv", drawn, zooms);
  Draw(c, "fep_all_families", body,
       three.family.empty() ? "no 3-ipp family found" :
                              "the 3-ipp family admissible for T in [" + Num(three.admissible_from, 6) + ", " +
                                  Num(three.admissible_to, 6) + "]");
}

FiguresResult DrawBarFigures(const Model& model, const BarSpec& bar, const OutputDir& dir, std::ostream& log) {
  // The bar's contact in space and time: the fixed-free bar starts from
  // rest in its place with the velocity of its first mode, the free end
  // moving towards the wall at 2 d w_1 (it would swing to 2 d: it strikes);
  // the exact integrator over three periods T_1. The map shows u(x, t) / d
  // along the bar, the impacts at its end marked; below, the end's u / d.
  const ModalBasis b = MakeModalBasis(model);
  const int n = model.dofs(), c = model.FirstContact().dof;
  const double w1 = b.omega[b.rigid], t1 = 2 * std::numbers::pi / w1, d = model.FirstContact().gap;
  Eigen::VectorXd shape = b.phi.col(b.rigid);
  shape *= 2.0 * d * w1 / shape[c];
  SimulateOptions opt;
  opt.t_end = 3.0 * t1;
  opt.sample_dt = t1 / 150.0;
  const double h = bar.length / bar.elements;
  const int first_node = bar.boundary == BarSpec::Boundary::kFixedFree ? 1 : 0;
  report::ResultFile out(dir, "bar_spacetime.csv");
  report::ResultFile tip(dir, "bar_spacetime_end.csv");
  report::ResultFile hits(dir, "bar_spacetime_impacts.csv");
  out << "t_ms,x,u_over_d\n";
  tip << "t_ms,u_over_d\n";
  hits << "t_ms,x\n";
  double u_max = 0.0, end_min = 0.0;
  SimulationObserver observer;
  observer.on_sample = [&](double t, const Eigen::VectorXd& z) {
    if (first_node == 1) out << 1e3 * t << ",0,0\n";
    for (int i = 0; i < n; ++i) {
      out << 1e3 * t << "," << (i + first_node) * h << "," << z[i] / d << "\n";
      u_max = std::max(u_max, std::abs(z[i]) / d);
    }
    out << "\n";
    tip << 1e3 * t << "," << z[c] / d << "\n";
    end_min = std::min(end_min, z[c] / d);
  };
  long impacts = 0;
  observer.on_impact = [&](const ContactEvent& e) {
    hits << 1e3 * e.t << "," << (c + first_node) * h << "\n";
    ++impacts;
  };
  const SimulationSummary s = Simulate(model, Eigen::VectorXd::Zero(n), shape, opt, observer);
  out.Commit();
  tip.Commit();
  hits.Commit();
  std::ostringstream body;
  const double m = std::max(1.0, std::ceil(u_max * 10) / 10);
  // Contours every 0.5 d, solid above 0 and dashed below, 0 solid grey:
  // the sign read in greyscale, where the diverging map's two ends are the
  // same grey (and near 0, where the other contours are far apart). (The
  // bar's label short, "u / d": a long one was cut in the column PDF; the
  // caption names the contours.)
  std::ostringstream positive, negative;
  for (double level = 0.5; level < m; level += 0.5) {
    positive << (level > 0.5 ? "," : "") << level;
    negative << (level > 0.5 ? "," : "") << -level;
  }
  body << "set datafile separator ','\nset contour base\nunset surface\nset view map\n";
  for (const auto& [block, levels] : {std::pair<const char*, std::string>{"$positive", positive.str()},
                                      {"$negative", negative.str()}, {"$zero", "0"}}) {
    // (B-splines through the grid's contour points: the grid's cells made
    // the lines jagged.)
    body << "set cntrparam bspline\nset cntrparam levels discrete " << levels << "\nset table " << block
         << "\nsplot 'bar_spacetime.csv' using 1:2:3 with lines notitle\nunset table\n";
  }
  body << "unset contour\nset surface\n";
  // The panels placed on the canvas (screen fractions), the colour bar
  // beside the map as high as it, each contour level drawn across the bar in
  // its contour's line: the bar is the contours' key (readers had asked
  // which level a line was).
  constexpr double kLeft = 0.12, kRight = 0.82, kMapBottom = 0.42, kMapTop = 0.97, kEndBottom = 0.11, kEndTop = 0.38;
  constexpr double kBarLeft = 0.84, kBarWidth = 0.03;
  body << "set multiplot\nset lmargin at screen " << kLeft << "\nset rmargin at screen " << kRight
       << "\nset bmargin at screen " << kMapBottom << "\nset tmargin at screen " << kMapTop
       << "\nset format x ''\nset ylabel 'position along the bar x (m)'\n"
       // (To x = L: the impacts marked there drawn whole over the frame's
       // edge, gnuplot clipping no point inside its range; a white strip
       // above L had read as a gap in the data.)
       << "set xrange [0:" << 1e3 * opt.t_end << "]\nset yrange [0:" << bar.length << "]\nset ytics "
       << NiceStep(0.0, bar.length, 4) << "\n"
       << style::Palette("displacement", "u / d") << "set cbrange [" << -m << ":" << m
       << "]\nset colorbox user origin screen " << kBarLeft << ", screen " << kMapBottom << " size screen " << kBarWidth
       << ", screen " << kMapTop - kMapBottom << "\nunset key\n";
  auto level_mark = [&](double level, const char* role) {
    const double y = kMapBottom + (level + m) / (2.0 * m) * (kMapTop - kMapBottom);
    body << "set arrow from screen " << kBarLeft << ", screen " << y << " to screen " << kBarLeft + kBarWidth
         << ", screen " << y << " nohead " << style::Look(role, "lines") << " front\n";
  };
  for (double level = 0.5; level < m; level += 0.5) {
    level_mark(level, "contour_positive");
    level_mark(-level, "contour_negative");
  }
  level_mark(0.0, "contour_zero");
  Plot map;
  // (The contour tables are written with spaces, read here through the
  // comma separator as one field of words.)
  const std::string words = " using (real(word(strcol(1), 1))):(real(word(strcol(1), 2)))";
  map.Unkeyed("'bar_spacetime.csv' using 1:2:3", "with image")
      .Unkeyed("$positive" + words, With("contour_positive"))
      .Unkeyed("$negative" + words, With("contour_negative"))
      // (Clear of x = 0, clamped, where u is 0 all along: its pieces there
      // looked like noise.)
      .Unkeyed("$zero using (real(word(strcol(1), 1))):(real(word(strcol(1), 2)) > " + Num(0.02 * bar.length) +
                   " ? real(word(strcol(1), 2)) : 1/0)",
               With("contour_zero"))
      .Unkeyed("'bar_spacetime_impacts.csv' using 1:2", With("impact"));
  body << map.str() << "unset arrow\nset bmargin at screen " << kEndBottom << "\nset tmargin at screen " << kEndTop
       << "\nunset colorbox\n"
       << "set format x '% g'\nset xlabel 'time t (ms)'\nset ylabel 'u(L) / d'\nset yrange ["
       << end_min - 0.15 * (1.0 - end_min) << ":" << 1.0 + 0.2 * (1.0 - end_min) << "]\nset ytics "
       << NiceStep(end_min, 1.0, 3) << "\n"
       // The key beside the panel, under the colour bar: nothing of the curve
       // under it. (In a row under the panels, it left a gap above it in the
       // PNG and wrapped in the column PDF: a reader preferred it here.)
       << "set key at screen 0.835, screen 0.33 left top Left reverse samplen 1.5 vertical\n";
  Plot end;
  end.Add("'bar_spacetime_end.csv' using 1:2", With("dof_contact"), "u(L)/d")
      .Add("1", With("obstacle"), "wall")
      .Add("'bar_spacetime_impacts.csv' using 1:(1)", With("impact"), "impacts", impacts);
  body << end.str() << "unset multiplot";
  log << "figures in " << dir.path().string() << ":\n";
  const ChartStatus chart = DrawChart(dir, "bar_spacetime", body.str());
  log << "  bar_spacetime: " << n << " dofs, 3 T_1 = " << Num(1e3 * opt.t_end, 4) << " ms, " << impacts
      << " impacts (simulation " << ToString(s.status) << ")" << (chart.drawn ? "" : ": not drawn: " + chart.message)
      << "\n" << (chart.drawn ? 1 : 0) << " figures drawn" << (chart.drawn ? "" : ", 1 failed") << "\n";
  return {chart.drawn ? 1 : 0, chart.drawn ? 0 : 1};
}

}  // namespace nsmodal::report
