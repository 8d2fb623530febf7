#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

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

// The sweep (first_rise.h) against the conservative search alone, on sums
// of 200 sinusoids at a chain's frequencies with random amplitudes and
// phases, the level put among the signal's highest values so that crossings come at
// all sorts of times (some none within the horizon). Both must stop at the
// same first crossing: a transversal one is finished by a Newton step to
// round-off (1e-13 here), a near-tangent one is located to about
// sqrt(tol / L2) ~ 1e-7, hence the 1e-6.
TEST(FirstRise, TheSweepStopsAtTheCrossingTheConservativeSearchFinds) {
  constexpr int kModes = 200;
  constexpr double kAgreement = 1e-6;
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Eigen::VectorXd w(kModes);
  for (int i = 0; i < kModes; ++i) w[i] = 2.0 * std::sin((i + 1) * M_PI / (2.0 * (2 * kModes + 1)));
  SinusoidSweep sweep(w);
  long plain_steps = 0, swept_steps = 0, grid_steps = 0, longest = 0;
  int found = 0;
  // The last 10 over a horizon 10 times longer: sweeps of more than 256 grid
  // steps, whose phasors are computed afresh on the way.
  for (int trial = 0; trial < 110; ++trial) {
    const double horizon = trial < 100 ? 300.0 : 3000.0;
    Eigen::VectorXd a(kModes), b(kModes);
    for (int i = 0; i < kModes; ++i) {
      const double amp = std::pow(unit(rng), 2), phase = 2.0 * M_PI * unit(rng);
      a[i] = amp * std::cos(phase);
      b[i] = amp * std::sin(phase);
    }
    SinusoidSum g(0.0, a, b, w);
    // The level 1.5 to 4 standard deviations of the signal above its mean.
    g.offset = -(1.5 + 2.5 * unit(rng)) * std::sqrt(0.5 * (a.squaredNorm() + b.squaredNorm()));
    const double tol = 1e-14 * g.bound[0];
    const FirstRiseResult plain = FirstRise(g, horizon, tol);
    const FirstRiseResult swept = FirstRise(g, horizon, tol, sweep);
    ASSERT_EQ(plain.found, swept.found) << "trial " << trial;
    EXPECT_NEAR(plain.s, swept.s, kAgreement) << "trial " << trial;
    if (swept.found) {
      // In the band, up to the evaluation of g at s itself: each phase w_i s
      // carries a rounding of a few eps w_i s, so g one of a few eps s L1.
      const double evaluation = 4.0 * std::numeric_limits<double>::epsilon() * swept.s * g.bound[1];
      EXPECT_GE(g.Position(swept.s), -tol - evaluation) << "trial " << trial;
    }
    found += swept.found;
    plain_steps += plain.steps;
    swept_steps += swept.steps;
    grid_steps += swept.sweep_steps;
    if (trial >= 100) longest = std::max(longest, swept.sweep_steps);
  }
  EXPECT_GT(longest, 256);  // a fresh start happened
  EXPECT_GT(found, 20);
  EXPECT_LT(found, 110);
  // The grid did the work: fewer conservative steps (each with 200 sin and cos).
  EXPECT_GT(grid_steps, 0);
  EXPECT_LT(swept_steps, plain_steps / 4);
}

// Peaks the grid could step over: Fejer-like sums of K cosines
// (1 / K) cos(k w0 (t - t*)), k = 1..K, w0 = 2 / K (all in phase at t*: the
// interpolation error there is near its worst case), the level `excess`
// below the peak, so g is above it only for a moment around t* (1e-4 wide
// for 1e-9), placed at 200 points across 2.7 (grid steps there are about 1).
// The sweep must stop where the conservative search alone does
// (agreement: both stop at the first crossing of the band, one Newton step
// or a near-tangent approach apart, within 1e-6 here). Removing the
// interpolants' error terms (L4 h^4 / 384, L6 h^6 / 46080) makes it step
// over some of these peaks (checked).
TEST(FirstRise, TheSweepCannotStepOverANarrowPeak) {
  long grid_steps = 0;
  for (const int terms : {8, 64}) {
    Eigen::VectorXd w(terms);
    for (int k = 0; k < terms; ++k) w[k] = (k + 1) * 2.0 / terms;
    SinusoidSweep sweep(w);
    for (const double excess : {1e-9, 1e-3}) {
      for (int j = 0; j < 200; ++j) {
        const double peak_at = 20.0 + 0.0137 * j;
        Eigen::VectorXd a(terms), b(terms);
        for (int k = 0; k < terms; ++k) {
          a[k] = std::cos(w[k] * peak_at) / terms;  // cos(w (t - t*)) = cos w t* cos w t + sin w t* sin w t
          b[k] = std::sin(w[k] * peak_at) / terms;
        }
        const SinusoidSum g(-1.0 + excess, a, b, w);
        const FirstRiseResult plain = FirstRise(g, 60.0, 1e-14);
        const FirstRiseResult swept = FirstRise(g, 60.0, 1e-14, sweep);
        ASSERT_TRUE(plain.found);
        ASSERT_TRUE(swept.found) << terms << " terms, peak at " << peak_at;
        EXPECT_NEAR(swept.s, plain.s, 1e-6) << terms << " terms, peak at " << peak_at << ", excess " << excess;
        grid_steps += swept.sweep_steps;
      }
    }
  }
  EXPECT_GT(grid_steps, 0);
}

}  // namespace
}  // namespace nsmodal
