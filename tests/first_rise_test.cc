#include <gtest/gtest.h>

#include <cmath>

#include "nsmodal/first_rise.h"

namespace nsmodal {
namespace {

SinusoidSum Wave(double offset, std::vector<double> a, std::vector<double> b, std::vector<double> w) {
  return SinusoidSum(offset, Eigen::Map<Eigen::VectorXd>(a.data(), a.size()),
                     Eigen::Map<Eigen::VectorXd>(b.data(), b.size()), Eigen::Map<Eigen::VectorXd>(w.data(), w.size()));
}

TEST(FirstRise, FindsATransversalCrossingToMachinePrecision) {
  const SinusoidSum g = Wave(-0.5, {-1.0}, {0.0}, {1.0});  // -cos t - 0.5, root at 2 pi / 3
  const FirstRiseResult r = FirstRise(g, 10.0, 1e-14);
  ASSERT_TRUE(r.found);
  EXPECT_NEAR(r.s, 2.0 * M_PI / 3.0, 1e-14);
}

// A drift (a rigid-body mode, flow.h's slope) whose vibration is round-off:
// g = -1 + t + 1e-30 cos(1e3 t). The quadratic step's usual form
// (-g' + sqrt(g'^2 - 2 L2 g)) / L2 is 0 to round-off there (L2 = 1e-24), and
// the search stalled at t = 0; the step must reach the root t = 1.
TEST(FirstRise, ANearlyAffineSignalIsSteppedToItsRoot) {
  SinusoidSum g = Wave(-1.0, {1e-30}, {0.0}, {1e3});
  g.slope = 1.0;
  g.UpdateBounds();
  const FirstRiseResult r = FirstRise(g, 10.0, 1e-14);
  ASSERT_TRUE(r.found);
  EXPECT_FALSE(r.stalled);
  EXPECT_NEAR(r.s, 1.0, 1e-14);
  // An exactly affine one (no sinusoid at all): the same root, at once.
  SinusoidSum line = Wave(-1.0, {}, {}, {});
  line.slope = 1.0;
  line.UpdateBounds();
  const FirstRiseResult l = FirstRise(line, 10.0, 1e-14);
  ASSERT_TRUE(l.found);
  EXPECT_NEAR(l.s, 1.0, 1e-14);
  EXPECT_LE(l.steps, 3);
}

TEST(FirstRise, CannotStepOverAShortExcursion) {
  // A slow wave that peaks 1e-9 above zero, plus a fast one that is large
  // elsewhere: the excursion lasts ~1e-4 and is found.
  const double peak = 1e-9;
  // -cos t - 1 + peak: -2 at t = 0, an excursion of height 1e-9 and width
  // ~9e-5 around t = pi; the root is at pi - acos(1 - peak).
  const SinusoidSum g = Wave(-1.0 + peak, {-1.0}, {0.0}, {1.0});
  const FirstRiseResult r = FirstRise(g, 7.0, 1e-15);
  ASSERT_TRUE(r.found);
  EXPECT_NEAR(r.s, M_PI - std::acos(1.0 - peak), 1e-9);
}

TEST(FirstRise, StartingInsideTheBandDoesNotReportTheSameContact) {
  // g(0) = 0 with g'(0) < 0 (just after an impact): the next root is the one at 2 pi.
  const SinusoidSum g = Wave(-1.0, {1.0}, {-0.1}, {1.0});  // cos t - 0.1 sin t - 1
  const FirstRiseResult r = FirstRise(g, 10.0, 1e-14);
  ASSERT_TRUE(r.found);
  EXPECT_GT(r.s, 6.0);
}

TEST(FirstRise, ATangencyFromRestLeavesTheBand) {
  // g = cos t - 1 touches 0 at t = 0 and 2 pi with zero slope (a release or a
  // graze): the search must neither stall at 0 nor miss the touch at 2 pi.
  const SinusoidSum g = Wave(-1.0, {1.0}, {0.0}, {1.0});
  const FirstRiseResult r = FirstRise(g, 10.0, 1e-14);
  ASSERT_TRUE(r.found);
  EXPECT_FALSE(r.stalled);
  EXPECT_NEAR(r.s, 2.0 * M_PI, 1e-6);  // a double root: located to sqrt(tol)
}

TEST(FirstRise, AGrazeThatEndsAboveTheBandIsNotReportedAgain) {
  // After a graze decided at g slightly above +tol, rising slowly to a peak
  // 5e-5 higher at t = 0.01: the search must not fire at s = 0 again (the
  // exact integrator looped forever there) but go on to the next rise,
  // after t = 2 pi - 0.01.
  const double tol = 1e-4;
  const SinusoidSum g = Wave(-1.0 + 2.0 * tol, {std::cos(0.01)}, {std::sin(0.01)}, {1.0});  // cos(t - 0.01) - 1 + 2 tol
  ASSERT_GT(g.Position(0.0), tol);
  const FirstRiseResult r = FirstRise(g, 10.0, tol);
  ASSERT_TRUE(r.found);
  EXPECT_GT(r.s, 2.0 * M_PI - 0.1);
}

TEST(FirstRise, TheNewtonFinishDoesNotJumpOverASlowTangency) {
  // -cos t - 1 + peak with peak = -0.9 tol: a touch inside the band, no
  // crossing. The armed search enters the band at slope ~sqrt(0.2 tol), where
  // a Newton step of tol / g' ~ 2.2 sqrt(tol) would jump past the peak at pi
  // and out of the band on the far side. The returned time must stay in the
  // band.
  const double tol = 1e-4, peak = -0.9 * tol;
  const SinusoidSum g = Wave(-1.0 + peak, {-1.0}, {0.0}, {1.0});
  const FirstRiseResult r = FirstRise(g, 7.0, tol);
  ASSERT_TRUE(r.found);
  EXPECT_GE(g.Position(r.s), -tol);
  EXPECT_LE(r.s, M_PI);
}

}  // namespace
}  // namespace nsmodal
