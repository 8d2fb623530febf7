#include <gtest/gtest.h>

#include <cmath>

#include "fixtures.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/transitions.h"
#include "nsmodal/two_impact.h"

namespace nsmodal {
namespace {

// An N = 3 system whose third mass is uncoupled has the 2-dof orbits (its
// third mode is not excited: r_3 = 0), so every result must agree to round-off.
constexpr double kTol = 1e-10;

TEST(NBody, UncoupledThirdMassReproducesTheTwoDofResults) {
  const AnalysisBasis b2 = testing::PaperBasis();
  const AnalysisBasis b3(testing::PaperPlusUncoupledMass());
  for (double period = 0.3; period < 30.0; period += 0.41) {
    const Orbit o2 = OneImpactOrbit(b2, period);
    const Orbit o3 = OneImpactOrbit(b3, period);
    EXPECT_NEAR(o3.energy, o2.energy, kTol * o2.energy) << period;
    EXPECT_EQ(o3.admissible, o2.admissible) << period;
    EXPECT_NEAR(o3.z0[0], o2.z0[0], kTol * o2.z0.norm());
    EXPECT_NEAR(o3.z0[2], 0.0, kTol * o2.z0.norm());  // x3 at rest
  }
  for (double period : {3.0, 6.0, 9.0, 20.5}) {
    const std::vector<double> r2 = TwoImpactRoots(b2, period);
    const std::vector<double> r3 = TwoImpactRoots(b3, period);
    ASSERT_EQ(r2.size(), r3.size()) << period;
    for (std::size_t k = 0; k < r2.size(); ++k) EXPECT_NEAR(r2[k], r3[k], 1e-10);
  }
  const std::vector<Transition> t2 = OneImpactTransitions(b2, 0.5, 30.0, 0.01);
  const std::vector<Transition> t3 = OneImpactTransitions(b3, 0.5, 30.0, 0.01);
  ASSERT_EQ(t2.size(), t3.size());
  for (std::size_t k = 0; k < t2.size(); ++k) EXPECT_NEAR(t2[k].period, t3[k].period, 1e-9);
}

TEST(NBody, CoupledMassMatrixOrbitsArePeriodic) {
  const AnalysisBasis b(testing::CoupledThreeDof());
  int potential = 0;
  for (double period = 0.5; period < 20.0; period += 0.77) {
    const Orbit o = OneImpactOrbit(b, period);
    if (o.potential) {
      ++potential;
      EXPECT_LT(o.periodicity_residual, 1e-12);
    }
    for (const Orbit& two : TwoImpactOrbits(b, period)) {
      if (two.potential) {
        EXPECT_LT(two.periodicity_residual, 1e-12) << period;
      }
    }
  }
  EXPECT_GT(potential, 20);
}

}  // namespace
}  // namespace nsmodal
