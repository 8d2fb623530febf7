// The tables and documents nsmodal writes: no inf or nan as a value
// (table.h, json.h). Issue 29 (1): a non-admissible orbit's first period has
// more impacts than predicted, and the extra one's time error was written as
// inf in validation.csv and response_validation.csv.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "chart.h"
#include "fixtures.h"
#include "nsmodal/json.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/response.h"
#include "nsmodal/scene.h"
#include "nsmodal/table.h"
#include "nsmodal/tables.h"
#include "nsmodal/validate.h"

namespace nsmodal {
namespace {

// The fields of a CSV line (no quoted commas in the tables checked here).
std::vector<std::string> Fields(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string f;
  while (std::getline(ss, f, ',')) out.push_back(f);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

// Every numeric field of every row finite or empty; returns the rows keyed by
// the header.
template <class Row>
std::vector<std::vector<std::string>> CheckedCsv(const report::Columns<Row>& columns, const std::vector<Row>& rows,
                                                 std::vector<std::string>* header) {
  std::ostringstream os;
  report::WriteCsv(os, columns, rows);
  std::istringstream in(os.str());
  std::string line;
  std::getline(in, line);
  *header = Fields(line);
  std::vector<std::vector<std::string>> out;
  while (std::getline(in, line)) {
    out.push_back(Fields(line));
    for (std::size_t k = 0; k < out.back().size() && k < columns.size(); ++k) {
      if (columns[k].kind != report::ColumnKind::kReal || out.back()[k].empty()) continue;
      EXPECT_TRUE(std::isfinite(std::stod(out.back()[k]))) << columns[k].name << " = " << out.back()[k];
    }
  }
  return out;
}

std::string Field(const std::vector<std::string>& header, const std::vector<std::string>& row,
                  const std::string& name) {
  for (std::size_t k = 0; k < header.size(); ++k) {
    if (header[k] == name) return row.at(k);
  }
  ADD_FAILURE() << "no column " << name;
  return {};
}

TEST(Tables, AMissingRealIsAnEmptyField) {
  const report::Columns<double> c{{"a", report::ColumnKind::kReal, [](const double& v) { return report::Real(v); }},
                                  {"b", report::ColumnKind::kReal, [](const double&) { return report::Real(std::nullopt); }}};
  std::ostringstream os;
  report::WriteCsvRow(os, c, 0.5);
  EXPECT_EQ(os.str(), "0.5,\n");
}

TEST(Tables, ANonFiniteValueIsABugTheWriterRefusesNamingTheColumn) {
  const report::Columns<double> c{{"energy", report::ColumnKind::kReal, [](const double& v) -> report::Cell { return v; }}};
  for (double bad : {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()}) {
    std::ostringstream os;
    try {
      report::WriteCsvRow(os, c, bad);
      ADD_FAILURE() << "wrote " << bad;
    } catch (const std::logic_error& e) {
      EXPECT_NE(std::string(e.what()).find(std::isnan(bad) ? "column energy holds nan" : "column energy holds inf"),
                std::string::npos)
          << e.what();
    }
    EXPECT_EQ(os.str(), "");  // nothing of the row written
  }
}

// `nsmodal validate configs/paper.toml --period 4.5:4.5:1 --impacts 1`: the
// 1-ipp orbit of T = 4.5 is not admissible, breaks in its first period with
// an extra impact, and has no impact-time error to give.
TEST(Tables, ANonAdmissibleOrbitsValidationRowHasNoInfOrNan) {
  const Model m = PaperModel();
  const AnalysisBasis b(m);
  const Orbit o = OneImpactOrbit(b, 4.5);
  ASSERT_TRUE(o.potential && !o.admissible) << o.reason;
  ValidateOptions opt;
  opt.periods = 30;
  const OrbitValidation v = ValidateOrbit(m, o, Integrator::kExact, opt);
  EXPECT_TRUE(v.consistent) << v.reason;
  ASSERT_NE(v.first_period_impacts, 1);
  EXPECT_FALSE(v.impact_time_error.has_value());
  std::vector<std::string> header;
  const auto rows = CheckedCsv(report::ValidationColumns(), std::vector<OrbitValidation>{v}, &header);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(Field(header, rows[0], "impact_time_error"), "");
  EXPECT_EQ(Field(header, rows[0], "first_period_impacts"), std::to_string(v.first_period_impacts));
  // An admissible orbit (T = 7.5) still has its error, a number.
  const OrbitValidation ok = ValidateOrbit(m, OneImpactOrbit(b, 7.5), Integrator::kExact, opt);
  ASSERT_TRUE(ok.impact_time_error.has_value());
  EXPECT_LT(*ok.impact_time_error, 1e-9);
  const ValidationReport report = SummarizeValidation({v, ok}, opt, 2);
  EXPECT_NE(report::ValidationJson(report, {v, ok}, ValidateSettings().Resolve({})).dump().find("\"passed\":true"), std::string::npos);
}

// `nsmodal response configs/forced.toml --frequency 0.4:1.0:0.05 --validate 3`:
// every row of response_validation.csv finite or empty, and the rows that
// broke in their first period (not admissible) have no time error.
TEST(Tables, ForcedValidationRowsHaveNoInfOrNan) {
  const Model m = LoadScene(NSMODAL_SOURCE_DIR "/configs/forced.toml").model;
  ResponseOptions ro;
  ro.grid = PeriodGrid{0.4, 1.0, 0.05};
  ro.fixed = 0.3;
  const ResponseCurve curve = ComputeResponse(m, ro);
  std::vector<ForcedOrbit> orbits;
  std::vector<ForcedValidationRow> rows;
  for (const ResponseBranch& br : curve.branches) orbits.insert(orbits.end(), br.points.begin(), br.points.end());
  ValidateOptions opt;
  opt.periods = 3;
  for (const ForcedOrbitValidation& v : ValidateForcedOrbits(m, orbits, opt)) rows.push_back({1, v});
  ASSERT_FALSE(rows.empty());
  std::vector<std::string> header;
  const auto csv = CheckedCsv(report::ForcedValidationColumns(), rows, &header);
  long extra = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const ForcedOrbitValidation& v = rows[i].v;
    const bool paired = v.first_period_impacts == v.orbit.impacts && v.orbit.impacts > 0;
    EXPECT_EQ(v.impact_time_error.has_value(), paired) << v.reason;
    EXPECT_EQ(Field(header, csv[i], "impact_time_error").empty(), !paired);
    extra += v.first_period_impacts > v.orbit.impacts;
  }
  EXPECT_GT(extra, 0) << "no row with an extra impact: the case is not exercised";
}

}  // namespace

// The 2-ipp roots of a sweep joined into branches (chart.h): at a fold in T,
// where two roots meet and vanish between two steps, the two branches are
// one curve (left apart, a steep curve was drawn in pieces with gaps); two
// branches leaving the trivial root t2 = T/2 at a pitchfork are not. Steps
// 0-10 at T = 1 + 0.1 k, every root at energy 1, a straight branch at
// t2 / T = 0.8 throughout.
namespace {

std::vector<report::FepTable::Root> Line(double u) {
  std::vector<report::FepTable::Root> roots;
  for (int k = 0; k <= 10; ++k) roots.push_back({k, 1.0 + 0.1 * k, u * (1.0 + 0.1 * k), 1.0, false});
  return roots;
}

// The "set arrow" lines of an inset script, each as its from x, from y, to
// x and to y expressions.
std::vector<std::vector<std::string>> Arrows(const std::string& script) {
  std::vector<std::vector<std::string>> out;
  std::istringstream in(script);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("set arrow from screen ", 0) != 0) continue;
    const std::size_t to = line.find(" to screen ");
    const std::size_t end = line.find(" nohead");
    if (to == std::string::npos || end == std::string::npos) continue;
    auto pair = [](const std::string& xy) {
      const std::size_t comma = xy.find(", screen ");
      return std::pair<std::string, std::string>{xy.substr(0, comma), xy.substr(comma + 9)};
    };
    const auto [fx, fy] = pair(line.substr(22, to - 22));
    const auto [tx, ty] = pair(line.substr(to + 11, end - to - 11));
    out.push_back({fx, fy, tx, ty});
  }
  return out;
}

// The x (a fraction of the main frame) where the inset's ground starts
// ("set object 1 rect from screen (ns_x0 + X * ...").
std::vector<double> GroundStarts(const std::string& script) {
  std::vector<double> out;
  const std::string key = "set object 1 rect from screen (ns_x0 + ";
  for (std::size_t at = script.find(key); at != std::string::npos; at = script.find(key, at + 1)) {
    out.push_back(std::stod(script.substr(at + key.size())));
  }
  return out;
}

}  // namespace

// An energy axis rounded up to a value its log ticks label names its top,
// even where rounding up lengthens the axis past two decades and thins the
// labels to 1 and 3 a decade (Fig. 18's top, 18.9, was not labelled).
TEST(Charts, AnAxisRoundedUpToALabelledValueNamesItsTop) {
  EXPECT_DOUBLE_EQ(report::LogLabelledTop(0.25, 18.9), 20.0);
  EXPECT_NE(report::LogTics("y", 0.25, 20.0).find("'20' 20"), std::string::npos);
  // 0.105 to 10.4: 1.995 decades, labelled 1, 2, 3, 5; rounded to 20 the
  // axis is 2.28 decades, labelled 1 and 3 only, and 20 is not one of them.
  EXPECT_EQ(report::LogTics("y", 0.105, 20.0).find("'20' 20"), std::string::npos);
  const double top = report::LogLabelledTop(0.105, 10.4);
  EXPECT_DOUBLE_EQ(top, 30.0);
  EXPECT_NE(report::LogTics("y", 0.105, top).find("'30' 30"), std::string::npos);
}

// A leader into an inset's foot (the inset above its window) rises its last
// stretch straight up, between the two period labels: slanted, leaders cut
// the labels "28.8" and "0.52" in the column PDF.
TEST(Charts, ALeaderRisesIntoAnInsetsFootBetweenItsPeriodLabels) {
  report::Occupancy free(0.0, 40.0, 0.1, 20.0);
  const report::Zoom z{9.0, 11.0, 0.3, 0.4, "B1"};
  const std::string script = report::ZoomInsets(free, report::Plot(), {z}, false);
  const std::vector<std::vector<std::string>> arrows = Arrows(script);
  ASSERT_EQ(arrows.size(), 2u) << script;  // to the ground's edge, then up
  EXPECT_EQ(arrows[1][0], arrows[1][2]) << "the last stretch is not vertical";
  EXPECT_EQ(arrows[0][2], arrows[1][0]) << "the two stretches do not meet";
  // Its x: the frame's left + f (its width), f halfway between the ticks
  // 9.5 and 10.5 of [9, 11] (TwoTickValues): 0.5.
  const std::string& x = arrows[1][0];
  const std::size_t plus = x.find(" ns_hc) + ");
  ASSERT_NE(plus, std::string::npos) << x;
  EXPECT_NEAR(std::stod(x.substr(plus + 10)), 0.5, 1e-6) << x;
}

// An inset keeps off the windows still to be zoomed on and the way up from
// each: on Fig. 3, the first inset sat right above the second's window,
// whose leader then ran through its labels.
TEST(Charts, AnInsetKeepsOffTheWayUpFromTheNextWindow) {
  report::Occupancy free(0.0, 40.0, 0.1, 20.0);
  // Two windows 4 apart (a tenth of the frame): an inset 27 % wide centred
  // above the first would cover the way up from the second.
  const std::vector<report::Zoom> zooms = {{9.5, 10.5, 0.3, 0.4, "A"}, {13.5, 14.5, 0.3, 0.4, "B"}};
  const std::vector<double> starts = GroundStarts(report::ZoomInsets(free, report::Plot(), zooms, false));
  ASSERT_EQ(starts.size(), 2u);
  const double second = free.X(14.0);
  EXPECT_FALSE(starts[0] - 0.02 < second && second < starts[0] + 0.27 + 0.02)
      << "the first inset (from " << starts[0] << ") covers the way up from the second window (at " << second << ")";
}

TEST(Charts, TwoBranchesMeetingAtAFoldAreOneCurve) {
  std::vector<report::FepTable::Root> roots = Line(0.8);
  // u = 0.3 +- 0.01 sqrt(10 - k), k = 0..9: they meet past step 9.
  for (int k = 0; k <= 9; ++k) {
    const double t = 1.0 + 0.1 * k, w = 0.01 * std::sqrt(10.0 - k);
    roots.push_back({k, t, (0.3 - w) * t, 1.0, false});
    roots.push_back({k, t, (0.3 + w) * t, 1.0, false});
  }
  const std::vector<std::vector<report::FepTable::Root>> branches = report::TwoImpactBranches(roots);
  ASSERT_EQ(branches.size(), 2u);
  std::size_t fold = branches[0].size() == 20 ? 0 : 1;
  ASSERT_EQ(branches[fold].size(), 20u);
  // Out along one branch, back along the other: the steps rise to 9, then fall.
  for (std::size_t i = 0; i < 20; ++i) EXPECT_EQ(branches[fold][i].step, i < 10 ? static_cast<int>(i) : 19 - static_cast<int>(i));
  EXPECT_EQ(branches[1 - fold].size(), 11u);
}

TEST(Charts, TwoBranchesLeavingTheTrivialRootAreNotJoined) {
  std::vector<report::FepTable::Root> roots = Line(0.8);
  // u = 0.5 +- 0.02 sqrt(k), k = 1..10: a pitchfork of t2 = T/2 before step 1.
  for (int k = 1; k <= 10; ++k) {
    const double t = 1.0 + 0.1 * k, w = 0.02 * std::sqrt(static_cast<double>(k));
    roots.push_back({k, t, (0.5 - w) * t, 1.0, false});
    roots.push_back({k, t, (0.5 + w) * t, 1.0, false});
  }
  EXPECT_EQ(report::TwoImpactBranches(roots).size(), 3u);
}

// The 3-ipp family's markers (its unstable rows marked at equal steps with
// the 2-ipp branches) keep clear of its stable orbits' dots: on paper.toml
// a square at T = 28.87 covered the stable dots at 28.85 and 28.86.
TEST(Charts, TheThreeImpactMarkersKeepClearOfItsStableOrbits) {
  report::FepTable table;
  Stability stable, unstable;
  stable.stable = true;
  for (int k = 0; k <= 200; ++k) {
    Orbit o;
    o.impacts = 3;
    o.admissible = true;
    o.period = 26.0 + 0.01 * k;
    o.times = {0.4 * o.period, 0.7 * o.period};
    o.energy = 0.4 + 0.01 * std::abs(k - 100);  // a V: steep enough to be marked along
    table.Add(k, o, k == 100 || k == 101 ? stable : unstable);
  }
  std::ostringstream csv;
  table.Write(csv);
  std::istringstream in(csv.str());
  std::string line;
  std::getline(in, line);  // the header
  std::vector<std::pair<bool, bool>> rows;  // (stable, marked)
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::vector<std::string> f;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) f.push_back(cell);
    ASSERT_EQ(f.size(), 7u) << line;
    ASSERT_EQ(f[0], "3-ipp");
    rows.push_back({f[4] == "1", f[6] == "1"});
  }
  ASSERT_EQ(rows.size(), 201u);
  int marks = 0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    if (!rows[k].second || rows[k].first) continue;
    ++marks;
    for (std::size_t j = k >= 3 ? k - 3 : 0; j <= std::min(k + 3, rows.size() - 1); ++j) {
      EXPECT_FALSE(rows[j].first) << "a marker at row " << k << ", beside the stable row " << j;
    }
  }
  EXPECT_GE(marks, 2);  // (marked at all: the check above is not empty)
}

}  // namespace nsmodal
