#pragma once
// The pieces every chart of the figures is made of (internal to the report
// library): a plot command built layer by layer with keys only for what is
// drawn, the context of a figure set, trajectories as CSV blocks, the energy
// axis, the frequency-energy table. Every series is drawn by its role in the
// one visual language (report/style.toml, style.h); no colour is named here.
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <functional>
#include <optional>
#include <ostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "nsmodal/atlas.h"
#include "nsmodal/check.h"
#include "nsmodal/figure_subjects.h"
#include "nsmodal/output.h"
#include "nsmodal/stability.h"
#include "nsmodal/style.h"

namespace nsmodal::report {

using style::With;

// A plot command built layer by layer. A layer with a key entry names how
// many points it draws: with none it is left out, so that a key lists what
// is drawn and nothing else (scripts/check_figure_colours.py checks the
// scripts against gnuplot's own table of each plotted curve).
//
// A panel of a multi-panel chart may collect its key entries instead of
// showing them (Keys::kCollected): the chart then shows one key for all its
// panels, a plot of legend-only entries (Legend: "NaN" layers, which draw
// nothing; the check accepts such an entry when another panel draws its
// style).
class Plot {
 public:
  enum class Keys { kShown, kCollected };
  struct Entry {
    std::string title, style;
  };
  explicit Plot(std::string command = "plot", Keys keys = Keys::kShown) : command_(std::move(command)), keys_(keys) {}
  // `spec`: the data and its columns ("'f.csv' using 1:2"); `style`: the
  // "with ..." clause (With(role)).
  // A spec may start with '' (gnuplot's "the previous file"): it is
  // resolved here, since the layer before it may have been left out.
  Plot& Add(const std::string& spec, const std::string& style, const std::string& title, long points = 1) {
    const std::string layer = Resolve(spec);
    if (points <= 0) return *this;
    if (keys_ == Keys::kShown) {
      layers_.push_back(layer + " " + style + " title '" + title + "'");
    } else {
      layers_.push_back(layer + " " + style + " notitle");
      collected_.push_back({title, style});
    }
    return *this;
  }
  // The key entries a Keys::kCollected plot drew.
  const std::vector<Entry>& Collected() const { return collected_; }
  // A plot of legend-only entries: each entry once, in order.
  static std::string Legend(const std::vector<Entry>& entries) {
    std::vector<std::string> seen;
    Plot legend;
    for (const Entry& e : entries) {
      if (std::find(seen.begin(), seen.end(), e.title) != seen.end()) continue;
      seen.push_back(e.title);
      legend.layers_.push_back("NaN " + e.style + " title '" + e.title + "'");
    }
    return legend.str();
  }
  // A key entry for a surface (pm3d has no key sample): gnuplot's
  // `keyentry`, a filled swatch of `style` ("with boxes fs solid ..."). (A
  // legend-only NaN layer with boxes in the splot drew every facet's border
  // black: Fig. 14's surface turned to a black mesh.)
  Plot& KeySwatch(const std::string& style, const std::string& title) {
    layers_.push_back("keyentry " + style + " title '" + title + "'");
    return *this;
  }
  // A key entry alone (a legend-only "NaN" layer), for a series drawn as
  // unkeyed layers (a line and its markers apart); the check accepts it
  // when those layers draw its style.
  Plot& KeyOnly(const std::string& style, const std::string& title) {
    if (keys_ == Keys::kShown) {
      layers_.push_back("NaN " + style + " title '" + title + "'");
    } else {
      collected_.push_back({title, style});
    }
    return *this;
  }
  // A layer with no key entry (drawn whatever its count).
  Plot& Unkeyed(const std::string& spec, const std::string& style) {
    layers_.push_back(Resolve(spec) + " " + style + " notitle");
    return *this;
  }
  bool empty() const { return layers_.empty(); }
  // (The key switched off for a plot with no entry, on for one with some:
  // gnuplot cleared an empty key's place, and the grid lines of Fig. 17's
  // panels broke at their top right corners.)
  std::string str() const {
    const bool keyed = std::any_of(layers_.begin(), layers_.end(),
                                   [](const std::string& layer) { return layer.find(" title '") != std::string::npos; });
    std::string out = keyed ? "set key on\n" : "set key off\n";
    out += command_ + " ";
    for (std::size_t k = 0; k < layers_.size(); ++k) out += (k ? ", \\\n  " : "") + layers_[k];
    return out + "\n";
  }
  // The same layers without key entries (and without the legend-only ones):
  // the plot again, as a zoom on a part of it.
  std::string Untitled() const {
    std::string out = command_ + " ";
    const char* sep = "";
    for (const std::string& layer : layers_) {
      if (layer.rfind("NaN ", 0) == 0) continue;
      const std::size_t at = layer.rfind(" title '");
      out += sep + (at == std::string::npos ? layer : layer.substr(0, at) + " notitle");
      sep = ", \\\n  ";
    }
    return out + "\n";
  }

 private:
  std::string Resolve(const std::string& spec) {
    if (spec.rfind("''", 0) == 0) {
      NSMODAL_CHECK(!last_source_.empty());
      return last_source_ + spec.substr(2);
    }
    if (!spec.empty() && (spec.front() == '\'' || spec.front() == '$')) {
      const std::size_t end = spec.front() == '\'' ? spec.find('\'', 1) + 1 : spec.find(' ');
      last_source_ = spec.substr(0, end);
    }
    return spec;
  }
  std::string command_, last_source_;
  Keys keys_ = Keys::kShown;
  std::vector<std::string> layers_;
  std::vector<Entry> collected_;
};

// A line of `role` drawn through `points` rows with about 12 of its markers
// along it, the line cut around each (gnuplot's pointinterval < 0: a line
// through an open marker filled it): for a family denser than a sweep,
// which MarkedLine's equal steps are not computed for.
inline std::string MarkersAlong(const char* role, long points) {
  return With(role, "linespoints") + " pi -" + std::to_string(std::max(1L, points / 12));
}

// A line of `role` (colour: `colour`, or the role's) with its markers at
// the rows whose column `mark` is 1 (EqualStepMarks), both unkeyed: the
// points of `source` with x and y where `condition` holds. (Keyed apart, as
// a line with markers: Plot::KeyOnly.)
inline void MarkedLine(Plot& plot, const std::string& source, const std::string& x, const std::string& condition,
                       const std::string& y, int mark, const char* role, const std::string& colour = "") {
  const std::string spec = source + " using " + x + ":(" + condition;
  plot.Unkeyed(spec + " ? " + y + " : 1/0)", With(role, "lines", colour))
      .Unkeyed(spec + " && $" + std::to_string(mark) + " == 1 ? " + y + " : 1/0)", With(role, "points", colour));
}

// A datablock NAME of vertical segments x = x_k from y = lo to y = hi (one
// per blank-line-separated block): transitions and stretch ends drawn as
// data, so that they are counted as what they are.
std::string VerticalLines(const std::string& name, const std::vector<double>& xs, double lo, double hi);

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
  const Model* model = nullptr;  // for the pictures that draw or simulate the system
  int drawn = 0, failed = 0;
};

// A number to `digits` significant digits, for keys, labels and notes (the
// CSVs and the printout carry the full ones).
std::string Num(double x, int digits = 4);

// Axis labels, in the paper's SI units (gnuplot enhanced text).
std::string DofLabel(const char* symbol, int dof, const char* unit);
std::string XcLabel(const Context& c);
// The contact displacement's symbol in keys, as on the axes: x_{2} for the
// paper's system (not x_c: one name per quantity on a chart).
std::string Xc(const Context& c);

// Draws NAME from `body` (report::DrawChart) and logs it. The data files
// must be closed (flushed) before. Figures carry no titles (captions go with
// the figure, docs/source/figures.md): `note` is the caption's numbers,
// printed beside the name.
void Draw(Context& c, const std::string& name, const std::string& body, const std::string& note = "",
          double aspect = 0.0);

bool IsStable(const std::optional<Stability>& s);

// Trajectory rows of one orbit: label, T, then OrbitTrajectory's columns.
void WriteTrajectoryHeader(std::ostream& os, const Context& c);
// `flight_rows` > 0: a row of NaN after every flight of that many rows but
// the last (the two rows of an impact are then not joined).
void WriteTrajectory(std::ostream& os, const std::string& label, double period, const Eigen::MatrixXd& tr,
                     long flight_rows = 0);
// Columns of a trajectory CSV (1-based for gnuplot): t, x_i, v_i.
int TCol();
int XCol(const Context&, int dof);

// Energy range and axes of a frequency-energy plot.
std::pair<double, double> EnergyRange(const Context& c);
// The top of an energy axis: 30 times the median of `energies` (not empty).
double EnergyTop(std::vector<double> energies);
// The labelled ticks of a log axis over [lo, hi]: 1, 2, 3, 5 per decade on
// up to two decades, 1 and 3 on up to three and a half, powers of 10
// beyond (a log axis with two labels is hard to read). With `ends`, lo and
// hi labelled too (to three digits), a tick near either left out; an end
// `beyond` what it stands for (values past it drawn at it: a colour bar's
// clamped ends) labelled with <= or >= before it.
struct Beyond {
  bool lo = false, hi = false;
};
std::string LogTics(const char* axis, double lo, double hi, bool ends = false, Beyond beyond = {});
// The least value at or above `hi` that LogTics labels on [lo, that value]:
// an axis ending there names its top.
double LogLabelledTop(double lo, double hi);
// About `ticks` ticks on [lo, hi] none of them within 0.4 of a step of its
// ends: on a 3-D chart's floor the two axes' end labels meet at a corner.
std::string InnerTics(const char* axis, double lo, double hi, int ticks);
// The ticks of a family's colour bar (the position along it, 0 to 1), at
// round values of its parameter, which runs from lo (0) to hi (1), and at
// its ends where no round value is near them.
std::string FamilyBarTics(double lo, double hi);
// A tick step of 1, 2 or 5 times a power of 10 giving about `ticks` ticks on
// [lo, hi] (small panels, 3-D axes and column PDFs need few).
double NiceStep(double lo, double hi, int ticks);
// gnuplot's y range of a chart of x_c over time whose curves span [lo, hi]:
// that and d, 8 % of it below and 12 % above, so the impacts on d clear the
// frame (rounded out to the ticks, ranges ran 0.5 to 1 d above d, empty;
// fitted without a margin, the impact dots met the frame).
std::string ContactTimeRange(const Context& c, double lo, double hi);
// About three ticks on [lo, hi], at least two of them labelled inside it.
double TwoTicksStep(double lo, double hi);
// Two ticks on [lo, hi], the first and the last of TwoTicksStep's, and as
// gnuplot's tic list "(a, b)".
std::pair<double, double> TwoTickValues(double lo, double hi);
std::string TwoTicks(double lo, double hi);
// One tick at `at` (four digits), as gnuplot's tic list "(a)".
std::string OneTick(double at);
// The period axis's end: the admissible orbits' longest period plus 5 %, on
// a multiple of 2 s, within the atlas's period grid; of the 1-ipp orbits
// alone when `one_only`.
double PeriodTop(const Context& c, bool one_only = false);
// The energy axis (log) and the period axis (0 to PeriodTop) of a frequency-energy plot.
std::string EnergyAxes(const Context& c, bool one_only = false);

void WriteBridges(std::ostream& out, const std::vector<Bridge>& bridges);
// Labels B1, B2, ... at the top of each bridge of the atlas (Figs. 8, 17,
// fep_all_families name them alike).
void BridgeLabels(const Context& c, std::ostream& body);

// The rows of a frequency-energy plot's CSV (family,T,t2,energy,stable,
// branch) of admissible orbits, grouped by family. A family with one orbit
// per period (1-ipp; the 2-ipp root t2 = T/2; the one 3-ipp family drawn) is
// a line, broken (a blank line) wherever a period of the grid has no
// admissible orbit of it. The other 2-ipp roots, several per period, are
// joined into branches (TwoImpactBranches) and drawn as lines too, marked
// every few points (filled dots stable, open circles unstable: told apart
// from the 1-ipp lines in greyscale); `branch` numbers them (0 elsewhere).
// Where the admissible 1-ipp stretch through step k of the atlas's sweep
// begins (Before: between steps k - 1 and k) or ends (After: k and k + 1) on
// a modal or grazing transition: the transition's orbit (step k's, at the
// transition's period and energy), to draw the stretch to its end (the
// branch rises steeply to a modal end: the last step fell short of its
// mark). Nothing where step k is not admissible or its neighbour is.
std::optional<Orbit> ZoneEndBefore(const Atlas& atlas, std::size_t k);
std::optional<Orbit> ZoneEndAfter(const Atlas& atlas, std::size_t k);

// A bridge's look: its role's, with a flat cap at each end (a bridge that
// ends short of a branch, as B4 does, read as reaching it).
std::string BridgeLook();

class FepTable {
 public:
  // The admissible orbits of an atlas's 1- and 2-ipp sweeps; a 1-ipp
  // stretch that ends on a modal or grazing transition between two steps
  // drawn to it (the transition's orbit as the stretch's end, its stability
  // the nearest step's: the branch rises steeply to a modal end, and the
  // last step fell short of its mark).
  void AddAtlas(const Atlas& atlas) {
    const auto& at = atlas.one.at;
    for (std::size_t k = 0; k < at.size(); ++k) {
      const OrbitRecord& r = at[k].front();
      if (const std::optional<Orbit> end = ZoneEndBefore(atlas, k)) Add(static_cast<int>(k), *end, r.stability);
      Add(static_cast<int>(k), r.orbit, r.stability);
      if (const std::optional<Orbit> end = ZoneEndAfter(atlas, k)) Add(static_cast<int>(k), *end, r.stability);
    }
    for (std::size_t k = 0; k < atlas.two.at.size(); ++k) {
      for (const OrbitRecord& r : atlas.two.at[k]) Add(static_cast<int>(k), r.orbit, r.stability);
    }
  }
  // `step`: the index of the orbit's period on its grid.
  void Add(int step, const Orbit& o, const std::optional<Stability>& s) {
    if (!o.admissible) return;
    const bool one = o.times.empty(), half = !one && o.impacts == 2 && IsHalfPeriodRoot(o), three = o.impacts == 3;
    if (!one && !half && !three) {
      roots_.push_back({step, o.period, o.times[0], o.energy, IsStable(s)});
      (IsStable(s) ? two_stable_ : two_unstable_) += 1;
      return;
    }
    if (three) {  // (its rows written with their marks: Write)
      three_rows_.push_back({step, o.period, o.times[0], o.energy, IsStable(s)});
      (IsStable(s) ? three_.stable : three_.unstable) += 1;
      three_.last = step;
      return;
    }
    Family& f = one ? one_ : half_;
    if (f.last >= 0 && step != f.last + 1 && step != f.last) f.rows << "\n";  // (the same step: a stretch's end)
    f.last = step;
    (IsStable(s) ? f.stable : f.unstable) += 1;
    f.rows << (one ? "1-ipp" : "2-ipp-half") << "," << o.period << "," << (one ? 0.0 : o.times[0])
           << "," << o.energy << "," << IsStable(s) << ",0,0\n";
  }
  // The plot of the CSV `csv` written by Write and of a bridges CSV with
  // `bridges` rows (WriteBridges): solid stable, dashed unstable. `index` >=
  // 0 selects that dataset of both files (gnuplot's `index`), where this
  // table is the index-th written.
  std::string Layers(const std::string& csv, const std::string& bridges, long bridge_count, int index = -1) const {
    Plot plot;
    AddLayers(plot, csv, bridges, bridge_count, index);
    return plot.str();
  }
  // The same layers added to `plot` (a chart with more layers).
  void AddLayers(Plot& plot, const std::string& csv, const std::string& bridges, long bridge_count, int index = -1) const {
    const std::string ix = index < 0 ? "" : " index " + std::to_string(index);
    auto select = [&](const char* family, const char* stable) {
      return "'" + csv + "'" + ix + " using 2:(strcol(1) eq '" + family + "'" + stable + " ? $4 : 1/0)";
    };
    // The key by family (kKeyTitles' order), first and alone; the layers
    // after it, unkeyed, in the drawing's order (the 1-ipp lines over the
    // 2-ipp branches they meet).
    const long counts[] = {one_.stable,   one_.unstable,   two_stable_,   two_unstable_, half_.stable,
                           half_.unstable, three_.stable, three_.unstable, bridge_count};
    const char* roles[] = {"one_stable", "one_unstable", "two_stable",   "two_unstable",   "two_half_stable",
                           "two_half",   "three_stable", "three_unstable", "bridge"};
    const char* kinds[] = {"", "", "linespoints", "linespoints", "", "", "linespoints", "linespoints", ""};  // as keyed
    for (std::size_t k = 0; k < kKeyTitles.size(); ++k) {
      if (counts[k] > 0) plot.KeyOnly(k + 1 == kKeyTitles.size() ? BridgeLook() : With(roles[k], kinds[k]), kKeyTitles[k]);
    }
    const std::string source = "'" + csv + "'" + ix;
    // The 3-ipp family, under the 2-ipp branch it runs along from
    // T = 26.7 to 29.3 on paper.toml (over it, its squares had hidden that
    // branch in every view; under it, they show beside it).
    // (A dot on every stable 3-ipp orbit: the stretch may be a few orbits,
    // too short a line to see. Markers along the unstable ones, at the rows
    // the table marks: in greyscale its dash-dot-dot was the dilated
    // branch's dash-dot.)
    if (three_.unstable > 0) MarkedLine(plot, source, "2", "strcol(1) eq '3-ipp' && $5 == 0", "$4", 7, "three_unstable");
    if (three_.stable > 0) plot.Unkeyed(select("3-ipp", " && $5 == 1"), With("three_stable", "linespoints"));
    // The 2-ipp branches: each a line with its markers at the rows the
    // table marks (equal steps along it).
    if (two_stable_ > 0) MarkedLine(plot, source, "2", "strcol(1) eq '2-ipp' && $5 == 1", "$4", 7, "two_stable");
    if (two_unstable_ > 0) MarkedLine(plot, source, "2", "strcol(1) eq '2-ipp' && $5 == 0", "$4", 7, "two_unstable");
    const std::string bridge = "'" + bridges + "'" + ix + " using 1:3:(0):($4-$3)";
    const std::tuple<std::string, std::string, long> layers[] = {
        {select("1-ipp", " && $5 == 1"), With("one_stable"), one_.stable},
        {select("1-ipp", " && $5 == 0"), With("one_unstable"), one_.unstable},
        // (The dilated branch's stability too: its changes are where B2's
        // foot and B4 leave it, on paper.toml.)
        {select("2-ipp-half", " && $5 == 1"), With("two_half_stable"), half_.stable},
        {select("2-ipp-half", " && $5 == 0"), With("two_half"), half_.unstable},
        // The bridges last, over a white halo that cuts the branches under
        // them (under the branches, two read as reaching a branch they did
        // not and B1 as a striped bar, in two readings).
        {bridge, With("halo", "vectors"), bridge_count},
        {bridge, BridgeLook(), bridge_count}};
    for (const auto& [spec, look, count] : layers) {
      if (count > 0) plot.Unkeyed(spec, look);
    }
  }
  // The key's entries, by family (Fig. 17 orders its panels' collected ones so).
  static constexpr std::array<const char*, 9> kKeyTitles = {
      "1-ipp, stable",  "1-ipp, unstable", "2-ipp, stable",   "2-ipp, unstable", "2-ipp, t_2 = T/2, stable",
      "2-ipp, t_2 = T/2, unstable", "3-ipp, stable", "3-ipp, unstable", "bridge"};
  // (`short_at_middle`: EqualStepMarks', for Fig. 17's panels, each zoomed
  // on one bridge, where a short stretch at a bridge's foot is the subject.)
  void Write(std::ostream& out, bool short_at_middle = false) const;

  struct Root {
    int step = 0;
    double period = 0.0, t2 = 0.0, energy = 0.0;
    bool stable = false;
  };

 private:
  struct Family {
    std::ostringstream rows;
    int last = -1;
    long stable = 0, unstable = 0;
  };
  Family one_, half_, three_;
  std::vector<Root> roots_;       // the 2-ipp roots off t2 = T/2
  std::vector<Root> three_rows_;  // the 3-ipp family's orbits, t2 their first impact
  long two_stable_ = 0, two_unstable_ = 0;
};

// The 2-ipp roots of consecutive steps joined into branches, in the plane
// (t2 / T, log E): a root continues the branch ending at the step before
// whose predicted next point (extrapolated from its last two) is within 0.05
// of it (|du| + |dv|; 0.25 of the last point for a branch of one point),
// the nearest pairs joined first; a root left over starts a branch. At a
// fold in T, where two roots meet and vanish between two steps, the two
// branches ending (or beginning) there adjacent in t2 / T are joined end to
// end, one reversed (left apart, a steep curve was pieces with gaps).
std::vector<std::vector<FepTable::Root>> TwoImpactBranches(std::vector<FepTable::Root> roots);

// Where to put a branch's markers: at equal steps of its length in the
// frame (9 % of it), the first point marked, not every k-th point (where a
// branch is steep its points crowd, and k-th markers made a chain of beads).
// With `short_at_middle`, a stretch shorter than a step is marked once, at
// its middle (Fig. 18's isolated pieces, Fig. 17's panels; on Figs. 8 and
// fep_all_families, whose short stretches end at the bridges, such a marker
// met the bridges' labels).
std::vector<std::vector<bool>> EqualStepMarks(const std::vector<std::vector<FepTable::Root>>& branches,
                                              bool short_at_middle = false);

// A window of a frequency-energy chart to zoom on: T and E (linear in the
// inset), its label in the inset's corner.
struct Zoom {
  double t_lo, t_hi, e_lo, e_hi;
  std::string label;
  double width = 0.27, height = 0.30;  // the inset's, as fractions of the frame
  bool one_period_tick = false;        // a single tick on T, the window's middle (a narrow inset)
  bool label_centred = false;          // the label at the top's middle, not its left (a curve's arm there)
};
// The periods a zoom on a short stretch [first, last] of a period axis
// `axis` wide shows: the stretch in the window's middle third, the window at
// least 2 * `min_half` of the axis wide. As (lo, hi).
std::pair<double, double> StretchWindow(double first, double last, double axis, double min_half = 0.005);
// The lowest and highest energies of `orbits` with a period in [t_lo, t_hi]
// (INFINITY and 0 where none is).
std::pair<double, double> EnergySpan(const std::vector<Orbit>& orbits, double t_lo, double t_hi);
// A family's stable stretches, each as its first and last period: its
// orbits added in order of period, each stable or not.
class StableStretches {
 public:
  void Add(double period, bool stable) {
    if (stable && !in_) stretches_.push_back({period, period});
    if (stable) stretches_.back().second = period;
    in_ = stable;
  }
  std::vector<std::pair<double, double>>& stretches() { return stretches_; }

 private:
  std::vector<std::pair<double, double>> stretches_;
  bool in_ = false;
};
// A frame's free space: which of its 100 x 100 cells something drawn
// crosses (T linear over [t_lo, t_hi], E over [e_lo, e_hi], logarithmic
// unless `log_e` is false).
class Occupancy {
 public:
  // What a cell holds: the chart's subject (an inset there hides it) or its
  // context (the potential orbits of Fig. 3: an inset avoids them if it can).
  // (kCorridor: the way from a window not yet zoomed on up to the top, where
  // its inset will likely go: another inset avoids it more than context.)
  static constexpr long kSubject = 1000, kCorridor = 30, kContext = 1;
  Occupancy(double t_lo, double t_hi, double e_lo, double e_hi, bool log_e = true);
  // A period and an energy as fractions of the frame.
  double X(double t) const;
  double Y(double e) const;
  // Their inverses: the period and the energy at fractions of the frame.
  double T(double fx) const;
  double E(double fy) const;
  // The cell at (fx, fy) holds at least `weight` (outside the frame: nothing).
  void Mark(double fx, double fy, long weight = kSubject);
  void MarkBox(double x0, double y0, double x1, double y1, long weight = kSubject);
  // A segment's cells, from (x0, y0) to (x1, y1) (fractions of the frame),
  // at `steps` + 1 equal steps.
  void MarkSegment(double x0, double y0, double x1, double y1, int steps);
  // The cells' weights summed over a box.
  long Count(double x0, double y0, double x1, double y1) const;

 private:
  static constexpr int kCells = 100;
  double t_lo_, t_hi_, e_lo_, e_hi_;
  bool log_e_;
  std::array<long, kCells * kCells> cells_{};
};

// The plot of a frequency-energy chart (EnergyAxes(c, one_only)) with an
// inset on each window, in the frame's freest place near it (the window
// boxed on the chart); a window with no free place is not zoomed.
std::string ZoomInsets(const Context& c, const Plot& plot, bool one_only, const std::vector<Zoom>& zooms);
// The same on any frame (T linear, E logarithmic) whose drawn things `free`
// holds; `in_multiplot`: the chart is one panel of a multiplot already.
std::string ZoomInsets(Occupancy free, const Plot& plot, const std::vector<Zoom>& zooms, bool in_multiplot);
// The zooms on each bridge too short to see at the chart's scale (under 4 %
// of the energy axis's height), and on `zooms` besides; `also`: orbits the
// chart draws besides the atlas's (an inset does not hide them).
std::string BridgeInsets(const Context& c, const Plot& plot, const std::vector<Orbit>& also = {},
                         const std::vector<Zoom>& zooms = {});
// The zooms on each stable stretch of the 1-ipp branch too short to see (under
// 1 % of the period axis), and on two marks of the chart on each other (under
// 1 % of the period axis and 4 % of the energy axis apart), on the 1-ipp
// chart (EnergyAxes(c, true)).
std::string StableStretchInsets(const Context& c, const Plot& plot);

// A layer circling the point (t, x) as `role` (a one-point datablock),
// keyed `title` unless it is empty.
void Mark(Plot& plot, double t, double x, const char* role, const std::string& title);
// Layers marking the points (t, d) where an orbit strikes the obstacle
// (keyed once, "impact: x_c = d").
std::function<void(Plot&)> ImpactMarks(const Context& c, const std::vector<double>& times);

// The set-up of a multi-panel chart's one key (Plot::Legend, the plot that
// follows): an invisible frame, the key centred at the foot of the canvas in
// up to three columns, in a band `height` high (screen fraction) that the
// panels leave free.
std::string LegendPanel(double height);
// Where a multi-panel chart's panels start (a gnuplot expression, a screen
// fraction): `labels` above the canvas's foot for the x labels, and the
// key's band, `band` of the height in the column PDF, scaled by the
// format's key_band (style.toml: fewer rows where more columns fit).
std::string KeyFoot(double labels, double band);

// The transitions of the 1-ipp family on a frequency-energy plot, written
// to CSV `name` (T,kind,energy): singular ones (T_S) as vertical lines
// (TransitionLines, drawn first: under the families), labelled above the
// frame; grazing ones (T_G) and, if `all`, the modal ones and the stability
// changes as marks at their energies (TransitionMarks, drawn last: over
// them); T_S and T_G labelled (the paper's captions name them).
void TransitionLines(Context& c, const std::string& name, bool all, std::ostream& body, Plot& plot);
void TransitionMarks(const Context& c, const std::string& name, bool all, Plot& plot);

// The pictures the dynamics needs, beside the paper's (dynamics_figures.cc):
// fig01_model, multipliers_one_impact, time_history, validation_orbits,
// fep_all_families. `three`: the 3-ipp family of Fig. 16.
void FigureModel(Context& c);
void FigureMultipliers(Context& c);
void FigureTimeHistory(Context& c);
void FigureValidation(Context& c, const ThreeImpactPick& three);
void FigureAllFamilies(Context& c, const ThreeImpactPick& three);

// A whole frequency-energy chart (Fig. 8, fep_all_families): `table` to the
// CSV `fep`, the atlas's bridges to `bridges`, its transitions to
// `transitions`; returns the gnuplot body: the energy axes, the families, the
// singular and grazing transitions, the bridges labelled B1, B2, ...
// `also`, `zooms`: orbits the table holds besides the atlas's, and windows
// to zoom on besides the bridges (BridgeInsets).
std::string FepChart(Context& c, const FepTable& table, const std::string& fep, const std::string& bridges,
                     const std::string& transitions, const std::vector<Orbit>& also = {},
                     const std::vector<Zoom>& zooms = {});

// The admissible 1- and 2-ipp orbits of 401 periods over [t - w, t + w]
// into `table`; returns the range of their energies (and, with `periods`,
// sets the range of their periods).
std::pair<double, double> AddOrbitsNear(const Context& c, double t, double w, FepTable& table,
                                        std::pair<double, double>* periods = nullptr);

}  // namespace nsmodal::report
