#include <gtest/gtest.h>

#include <cmath>

#include "nsmodal/one_impact.h"
#include "nsmodal/simulate.h"
#include "nsmodal/transitions.h"
#include "nsmodal/work_precision.h"

namespace nsmodal {
namespace {

WorkPrecisionOptions Quick() {
  WorkPrecisionOptions o;
  o.quick = true;
  return o;
}

const GrazingRow* Find(const std::vector<GrazingRow>& rows, double delta, const std::string& side,
                       const std::string& setting) {
  for (const GrazingRow& r : rows) {
    if (r.delta == delta && r.side == side && r.setting == setting) return &r;
  }
  return nullptr;
}

TEST(Grazing, ExactCountsMatchTheAnalyticOrbitOnBothSidesOfTheTransition) {
  // The reference counts are the analytic facts, not another simulation: on
  // the admissible side (clearance < 0) the 1-ipp orbit has no impact before
  // its nominal one at T; past grazing the flight crosses d, so the first
  // period holds at least one more impact.
  const std::vector<GrazingRow> rows = RunGrazingFailures(Quick());
  ASSERT_FALSE(rows.empty());
  for (const GrazingRow& r : rows) {
    if (r.integrator != "exact" || r.setting != "root_tol=1e-14") continue;
    if (r.side == "below") {
      EXPECT_LT(r.clearance, 0.0);
      EXPECT_EQ(r.impacts, 0) << "delta " << r.delta;
    } else {
      EXPECT_GT(r.clearance, 0.0);
      EXPECT_GE(r.impacts, 1) << "delta " << r.delta;
    }
  }
}

TEST(Grazing, MoreauJeanMakesASpuriousImpactWhenItsErrorExceedsTheClearance) {
  // Near the tangency the velocity is ~0 and Moreau-Jean's position error is
  // ~ |a_c| h^2 (bench: the clearance it respects scales as h^2, 3.5e-4 at
  // h = 1e-2, 3.5e-6 at 1e-3). With h = 1e-2 an admissible orbit
  // that clears d by 3.5e-4 (delta = 1e-4) is respected, one that clears it by
  // 3.5e-7 (delta = 1e-7) is not, and gets an impact it does not have. The
  // event-driven integrators respect both.
  const std::vector<GrazingRow> rows = RunGrazingFailures(Quick());
  const GrazingRow* wide = Find(rows, 1e-4, "below", "step=1e-02");
  const GrazingRow* narrow = Find(rows, 1e-7, "below", "step=1e-02");
  ASSERT_NE(wide, nullptr);
  ASSERT_NE(narrow, nullptr);
  EXPECT_EQ(wide->impacts, 0);
  EXPECT_GT(narrow->impacts, 0);
  for (const char* setting : {"root_tol=1e-06", "rtol=1e-06", "rtol=1e-10"}) {
    const GrazingRow* r = Find(rows, 1e-7, "below", setting);
    ASSERT_NE(r, nullptr) << setting;
    EXPECT_EQ(r->impacts, 0) << setting;
  }
}

TEST(Grazing, ExactAtAContactBandAsWideAsTheExcursionFinishes) {
  // The regression behind FirstRise's rise rule: at T_G - 1e-4 with
  // root_tol = 1e-4 the excursion above d ends inside the contact band; the
  // search used to report the same graze at s = 0 forever.
  const Model m = PaperModel();
  const AnalysisBasis b(m);
  const double tg = OneImpactTransitions(b, 9.0, 9.3, 0.01).front().period;
  for (double delta : {1e-4, 1e-6, 1e-8}) {
    const Orbit o = OneImpactOrbit(b, tg - delta);
    SimulateOptions opt;
    opt.t_end = 3.0 * o.period;
    opt.sample_dt = 0.0;
    opt.root_tol = delta;
    opt.max_steps = 100000;  // a finished run takes < 200
    const SimulationSummary r = Simulate(m, o.z0.head(2), o.z0.tail(2), opt);
    EXPECT_EQ(r.status, SimulationStatus::kFinished) << "delta " << delta << ": " << r.message;
  }
}

TEST(Grazing, SummaryKeepsTheLimitBeforeTheFirstFailure) {
  // Excursions 1e-3 (right), 1e-4 (wrong), 1e-5 (right again by chance): the
  // limit is 1e-3, the last right one before the first failure. Clearances
  // all right: the smallest tried.
  std::vector<GrazingRow> rows;
  for (auto [c, ok] : {std::pair{1e-3, true}, {1e-4, false}, {1e-5, true}}) {
    rows.push_back({0.0, "above", "x", "s", ok ? 2 : 1, 2, c});
    rows.push_back({0.0, "below", "x", "s", 0, 0, -c});
  }
  rows.push_back({0.0, "above", "y", "s", 0, 2, 1e-2});  // wrong at the largest
  const std::vector<GrazingLimit> limits = SummarizeGrazing(rows);
  ASSERT_EQ(limits.size(), 2u);
  EXPECT_EQ(limits[0].shallowest_excursion, 1e-3);
  EXPECT_EQ(limits[0].smallest_clearance, 1e-5);
  EXPECT_TRUE(std::isinf(limits[1].shallowest_excursion));
}

TEST(WorkPrecision, EveryIntegratorConvergesAndExactHoldsOverTheLongHorizon) {
  const std::vector<WorkPrecisionRow> rows = RunWorkPrecision(Quick());
  auto error = [&](const std::string& c, const std::string& integrator, double value) {
    for (const WorkPrecisionRow& r : rows) {
      if (r.case_name == c && r.integrator == integrator && r.setting_value == value) return r.error;
    }
    ADD_FAILURE() << c << " " << integrator << " " << value << " missing";
    return std::nan("");
  };
  for (const char* c : {"smooth", "high-energy", "zeno"}) {
    // A tighter setting by four decades (cvode) or one (Moreau-Jean, first
    // order) must cut the error by at least 10 (cvode) or 5 (Moreau-Jean, its
    // constant varies between settings by less than a factor 2, see README).
    EXPECT_LT(error(c, "cvode-adams", 1e-10), 0.1 * error(c, "cvode-adams", 1e-6)) << c;
    EXPECT_LT(error(c, "cvode-bdf", 1e-10), 0.1 * error(c, "cvode-bdf", 1e-6)) << c;
    EXPECT_LT(error(c, "moreau-jean", 1e-3), 0.2 * error(c, "moreau-jean", 1e-2)) << c;
  }
  // 100 periods of a stable orbit: the exact integrator at a loose contact
  // band still lands within 1e-11 of the reference (impact times are
  // Newton-finished to machine precision whatever the band).
  EXPECT_LT(error("long-100", "exact", 1e-6), 1e-11);
}

}  // namespace
}  // namespace nsmodal
