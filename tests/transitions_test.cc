#include <gtest/gtest.h>

#include <cmath>

#include "fixtures.h"
#include "nsmodal/admissibility.h"
#include "nsmodal/flow.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/transitions.h"

namespace nsmodal {
namespace {

// Target: transitions located to 1e-9 in T.
constexpr double kLocationTarget = 1e-9;

TEST(Transitions, SingularPeriodsAreRootsOfEq23WithDivergingEnergy) {
  const AnalysisBasis b = testing::PaperBasis();
  const std::vector<double> ts = SingularPeriods(b, 0.1, 40.0);
  ASSERT_GE(ts.size(), 5u);
  for (double t : ts) {
    // D(T) crosses zero there, and the energy of the 1-ipp orbit grows as 1/(T - T_S)^2.
    EXPECT_GT(SingularFunction(b, t - 1e-6), 0.0);
    EXPECT_LT(SingularFunction(b, t + 1e-6), 0.0);
    EXPECT_GT(OneImpactOrbit(b, t + 1e-7).energy, 100.0 * OneImpactOrbit(b, t + 1e-3).energy);
  }
}

TEST(Transitions, PaperSystemOnZeroToForty) {
  const AnalysisBasis b = testing::PaperBasis();
  const std::vector<Transition> tr = OneImpactTransitions(b, 0.05, 40.0, 0.01);
  int singular = 0, modal = 0, grazing = 0;
  for (const Transition& t : tr) {
    singular += t.kind == TransitionKind::kSingular;
    modal += t.kind == TransitionKind::kModal;
    grazing += t.kind == TransitionKind::kGrazing;
  }
  EXPECT_GE(singular, 1);
  EXPECT_GE(modal, 1);
  EXPECT_GE(grazing, 1);
  const Eigen::VectorXd linear = b.Periods();
  for (const Transition& t : tr) {
    if (t.kind == TransitionKind::kModal) {
      // T = k T_i exactly (eq. 24), the orbit a linear mode grazing d.
      bool multiple = false;
      for (int i = 0; i < b.n; ++i) multiple = multiple || std::abs(std::remainder(t.period, linear[i])) < 1e-12 * t.period;
      EXPECT_TRUE(multiple) << t.period;
    }
    if (t.kind == TransitionKind::kGrazing) {
      // An interior maximum of x_c touches d.
      EXPECT_NEAR(GrazingFunction(b, t.period), 0.0, 1e-9) << t.period;
    }
  }
}

TEST(Transitions, LocationDoesNotDependOnTheGrid) {
  const AnalysisBasis b = testing::PaperBasis();
  const std::vector<Transition> coarse = OneImpactTransitions(b, 0.05, 40.0, 0.01);
  const std::vector<Transition> fine = OneImpactTransitions(b, 0.05, 40.0, 0.0013);
  ASSERT_EQ(coarse.size(), fine.size());
  for (std::size_t k = 0; k < coarse.size(); ++k) {
    EXPECT_EQ(coarse[k].kind, fine[k].kind);
    EXPECT_NEAR(coarse[k].period, fine[k].period, kLocationTarget);
  }
}

TEST(Transitions, AdmissibilityFlipsAcrossEachTransition) {
  const AnalysisBasis b = testing::PaperBasis();
  for (const Transition& t : OneImpactTransitions(b, 0.05, 40.0, 0.01)) {
    const double delta = 1e-6 * t.period;
    EXPECT_NE(OneImpactOrbit(b, t.period - delta).admissible, OneImpactOrbit(b, t.period + delta).admissible)
        << ToString(t.kind) << " at " << t.period;
  }
}

}  // namespace
}  // namespace nsmodal
