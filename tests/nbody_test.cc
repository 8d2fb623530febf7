#include <gtest/gtest.h>

#include <cmath>

#include "fixtures.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/transitions.h"
#include "nsmodal/model.h"
#include "nsmodal/stability.h"
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

namespace nsmodal {
namespace {

Model Chain(int n) {
  return MakeChain(std::vector<double>(n, 1.0), std::vector<double>(n, 1.0), n - 1, 1.0, 1.0);
}

// Issue 12: the closed-form 1-ipp orbit (O(N)) is the kernel of A_1 found by
// SVD (O(N^3)), for N = 2, 10, 100. 1e-10 relative: the SVD kernel vector's
// error is ~eps / (the next singular value), which is >= 1.1e-2 at these
// periods (measured), and the agreement measured is <= 2.6e-14.
TEST(NBody, ClosedFormOneImpactOrbitIsTheSvdKernelForLargeChains) {
  for (int n : {2, 10, 100}) {
    const AnalysisBasis b(Chain(n));
    for (double period : {3.3, 7.9, 15.1}) {
      const Orbit closed = OneImpactOrbit(b, period);
      const Orbit svd = OneImpactOrbitFromKernel(b, period);
      ASSERT_TRUE(closed.potential) << "N = " << n << " T = " << period;
      EXPECT_LT((closed.y0 - svd.y0).norm(), 1e-10 * closed.y0.norm()) << "N = " << n << " T = " << period;
    }
  }
}

// Issue 12: a 10-mass chain with an 11th mass on its own spring, uncoupled
// from the contact, has the 10-mass chain's orbits, roots and multipliers,
// plus the 11th mode's rotation e^(+-i w T).
TEST(NBody, UncoupledMassReproducesTheTenMassChain) {
  const Model small = Chain(10);
  Model big = small;
  big.mass = Eigen::MatrixXd::Identity(11, 11);
  big.stiffness = Eigen::MatrixXd::Zero(11, 11);
  big.stiffness.topLeftCorner(10, 10) = small.stiffness;
  big.stiffness(10, 10) = 3.0;
  big.contacts = {DofContact(11, small.FirstContact().dof, true, small.FirstContact().gap, 1.0)};
  const AnalysisBasis b10(small), b11(big);
  for (double period : {4.3, 9.7, 18.1}) {
    const Orbit o10 = OneImpactOrbit(b10, period), o11 = OneImpactOrbit(b11, period);
    EXPECT_NEAR(o11.energy, o10.energy, kTol * o10.energy) << period;
    EXPECT_EQ(o11.admissible, o10.admissible) << period;
    const Stability s10 = OrbitStability(b10, o10), s11 = OrbitStability(b11, o11);
    EXPECT_EQ(s10.stable, s11.stable) << period;
    EXPECT_NEAR(s10.max_modulus, s11.max_modulus, kTol * s10.max_modulus) << period;
    for (int k = 0; k < s10.multipliers.size(); ++k) {
      double nearest = INFINITY;
      for (int j = 0; j < s11.multipliers.size(); ++j) nearest = std::min(nearest, std::abs(s11.multipliers[j] - s10.multipliers[k]));
      EXPECT_LT(nearest, 1e-8) << period;  // the structured spectrum's accuracy (stability_test)
    }
    const std::vector<double> r10 = TwoImpactRoots(b10, period), r11 = TwoImpactRoots(b11, period);
    ASSERT_EQ(r10.size(), r11.size()) << period;
    for (std::size_t k = 0; k < r10.size(); ++k) EXPECT_NEAR(r10[k], r11[k], kTol * period);
  }
}

}  // namespace
}  // namespace nsmodal
