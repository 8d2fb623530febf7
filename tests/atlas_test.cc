#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "fixtures.h"
#include "nsmodal/atlas.h"
#include "nsmodal/error.h"
#include "nsmodal/figure_subjects.h"
#include "nsmodal/one_impact.h"

namespace nsmodal {
namespace {

// The transitions are refined by Brent to ~1e-15 (transitions.h); the
// README prints them to 3 decimals: 5e-4 compares with those.
constexpr double kPrinted = 5e-4;

class PaperAtlas : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    basis_ = new AnalysisBasis(PaperModel());
    atlas_ = new Atlas(ComputeAtlas(*basis_, PeriodGrid{0.05, 40.0, 0.05}));
  }
  static void TearDownTestSuite() {
    delete atlas_;
    delete basis_;
  }
  static AnalysisBasis* basis_;
  static Atlas* atlas_;
};
AnalysisBasis* PaperAtlas::basis_ = nullptr;
Atlas* PaperAtlas::atlas_ = nullptr;

TEST_F(PaperAtlas, TwelveTransitionsOnZeroToForty) {
  int count[5] = {0, 0, 0, 0, 0};
  for (const Transition& t : atlas_->transitions) ++count[static_cast<int>(t.kind)];
  EXPECT_EQ(count[static_cast<int>(TransitionKind::kSingular)], 3);
  EXPECT_EQ(count[static_cast<int>(TransitionKind::kModal)], 6);
  EXPECT_EQ(count[static_cast<int>(TransitionKind::kGrazing)], 3);
  // And the stability changes inside the zones (stability_test checks their
  // values): three through +1, three through -1.
  EXPECT_EQ(count[static_cast<int>(TransitionKind::kMultiplierPlusOne)], 3);
  EXPECT_EQ(count[static_cast<int>(TransitionKind::kMultiplierMinusOne)], 3);
}

TEST_F(PaperAtlas, FourBridgesThreeGrazingOneAtAPeriodDoubling) {
  ASSERT_EQ(atlas_->bridges.size(), 4u);
  const double expected[] = {9.127, 19.242, 29.307, 14.572};  // grazing first, then period doubling
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(atlas_->bridges[k].period, expected[k], kPrinted);
    EXPECT_EQ(atlas_->bridges[k].kind, k < 3 ? BridgeKind::kGrazing : BridgeKind::kPeriodDoubling);
  }
  // The doublings at 9.4907 (a pitchfork) and 9.6211 (the paper's bridge) are
  // said, not drawn twice.
  ASSERT_EQ(atlas_->notes.size(), 2u);
  EXPECT_NE(atlas_->notes[0].find("pitchfork"), std::string::npos) << atlas_->notes[0];
  EXPECT_NE(atlas_->notes[1].find("grazing one"), std::string::npos) << atlas_->notes[1];
}

TEST_F(PaperAtlas, SweepsHoldEveryPeriodAndTheAdmissibleStability) {
  EXPECT_EQ(atlas_->one.periods.size(), 800u);
  EXPECT_EQ(atlas_->one.Count(), 800);
  for (const auto& list : atlas_->two.at) {
    for (const OrbitRecord& r : list) {
      EXPECT_TRUE(r.orbit.potential);
      // The policy of an atlas: stability for the admissible orbits only
      // (bridge ends, grazing, have none: stability.h).
      if (!r.orbit.admissible) {
        EXPECT_FALSE(r.stability.has_value());
      }
    }
  }
  EXPECT_GT(atlas_->two.Admissible(), 0);
}

TEST_F(PaperAtlas, FigureSubjectsAreThoseOfThePaper) {
  const Bridge* paper = PaperBridge(*atlas_);
  ASSERT_NE(paper, nullptr);
  EXPECT_NEAR(paper->period, 19.242, kPrinted);  // the graze at T/2 (Figs. 13-15)
  const ModalPick modal = PickModalTransition(*basis_, *atlas_);
  EXPECT_NEAR(modal.period, 2.0 * basis_->Periods().minCoeff(), 1e-12);  // 2 T_1 (Figs. 4, 10)
  EXPECT_NE(modal.side, 0);
  const std::optional<TwoGrazes> two = TwoGrazesExample(*basis_, *atlas_);
  ASSERT_TRUE(two.has_value());
  EXPECT_NEAR(two->bridge->period, 9.127, kPrinted);  // Fig. 9
  EXPECT_TRUE(two->three.admissible);
  // Fig. 2 fails NC2 and NC3 but is in ker A_2: periodic to round-off
  // (potential orbits measure ~1e-14, admissibility.h), x_c(t2) = d / 2
  // (nc2_residual 0.5 up to the kernel's round-off), above d between impacts.
  const std::optional<Orbit> fig2 = NotAdmissibleExample(*basis_, *atlas_);
  ASSERT_TRUE(fig2.has_value());
  EXPECT_LT(fig2->periodicity_residual, 1e-12);
  EXPECT_NEAR(fig2->nc2_residual, 0.5, 1e-12);
  EXPECT_GT(fig2->max_excess, 0.05 * basis_->gap);
  EXPECT_FALSE(fig2->potential || fig2->admissible);
  const ModeBranch branch = TwoImpactModeBranch(*basis_);
  EXPECT_FALSE(branch.run.empty()) << branch.why_not;
}

TEST(PeriodGrid, ParsesAndRefusesNamingTheField) {
  const PeriodGrid g = PeriodGrid::Parse("0.05:40:0.01");
  EXPECT_EQ(g.Count(), 3996);
  EXPECT_DOUBLE_EQ(g.Values().back(), 0.05 + 3995 * 0.01);
  for (const char* bad : {"1:2", "5:1:0.1", "1:2:0", "a:2:0.1", "0:1:0.1", "1:1e8:1", "1:nan:0.1"}) {
    try {
      PeriodGrid::Parse(bad, "--period");
      ADD_FAILURE() << "accepted " << bad;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "--period") << bad;
    }
  }
}

// Issue 29 item 4: the work of an analysis is estimated before it starts
// (work.h), and one beyond kMaxSweepWork is refused at once.
TEST(WorkLimit, TwoImpactPeriodJustBelowTheLimitIsAcceptedJustAboveRefused) {
  const AnalysisBasis b(PaperModel());
  // The period where one 2-ipp period's estimate reaches the limit (the
  // estimate grows with T): bisection.
  double lo = 1.0, hi = 1e5;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (SweepWork(b, mid, 0.0, 1, 2) <= kMaxSweepWork ? lo : hi) = mid;
  }
  EXPECT_GT(lo, 5000.0);  // T = 5,000 (about 30 s on one core) is accepted
  EXPECT_NO_THROW(CheckSweepWork(b, PeriodGrid{0.99 * lo, 0.99 * lo, 1.0}, {2}));
  try {
    CheckSweepWork(b, PeriodGrid{1.01 * lo, 1.01 * lo, 1.0}, {2}, "--period");
    ADD_FAILURE() << "T = " << 1.01 * lo << " accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--period");
    EXPECT_NE(std::string(e.what()).find("the limit is"), std::string::npos) << e.what();
  }
}

TEST(WorkLimit, TheIssuesSweepIsRefusedBeforeAnyWork) {
  const AnalysisBasis b(PaperModel());
  // T = 10,000 ran for minutes (4.5e7 roots); refused now in microseconds.
  EXPECT_THROW(ComputeSweep(b, PeriodGrid{10000.0, 10000.0, 1.0}, 2), InputError);
  EXPECT_THROW(OrbitsAt(b, 10000.0, 2), InputError);
  // The 1-ipp orbit of that period is cheap (one flight: 6.7e3 roots).
  EXPECT_NO_THROW(OrbitsAt(b, 10000.0, 1));
}

TEST(WorkLimit, TheEstimateBoundsTheRootsFound) {
  const AnalysisBasis b(PaperModel());
  for (double period : {40.0, 400.0, 1000.0}) {
    EXPECT_LE(static_cast<double>(TwoImpactRoots(b, period).size()), HalfOscillations(b, period)) << period;
  }
}

// validate's manifold check takes the family's state alone (no NC3 search):
// the same state as the evaluated orbit's.
TEST(WorkLimit, OneImpactStateIsTheOrbitsState) {
  const AnalysisBasis b(PaperModel());
  for (double period : {2.0, 7.5, 33.3}) EXPECT_EQ(OneImpactState(b, period), OneImpactOrbit(b, period).y0) << period;
}

TEST(WorkLimit, TheDocumentedRunsStayWithinIt) {
  const AnalysisBasis paper(PaperModel());
  // scripts/quickstart.sh and `nsmodal figures` (both sweeps and the transitions).
  EXPECT_NO_THROW(CheckSweepWork(paper, PeriodGrid{0.05, 40.0, 0.001}, {1}, "period", true));
  EXPECT_NO_THROW(CheckSweepWork(paper, PeriodGrid{0.05, 40.0, 0.01}, {2}));
  EXPECT_NO_THROW(CheckSweepWork(paper, PeriodGrid{0.01, 41.0, 0.01}, {1, 2}, "period", true));
  // bench_analytic: the 1-ipp sweep of a chain of 1,000 unit masses.
  const int n = 1000;
  const AnalysisBasis chain(MakeChain(std::vector<double>(n, 1.0), std::vector<double>(n, 1.0), n - 1, 1.0, 1.0));
  EXPECT_NO_THROW(CheckSweepWork(chain, PeriodGrid{0.5, 60.0, 0.01}, {1}));
}

}  // namespace
}  // namespace nsmodal
