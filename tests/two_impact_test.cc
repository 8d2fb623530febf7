#include <gtest/gtest.h>

#include <gsl/gsl_errno.h>

#include <cmath>

#include "fixtures.h"
#include "nsmodal/error.h"
#include "nsmodal/explore.h"
#include "nsmodal/transitions.h"
#include "nsmodal/return_map.h"
#include "nsmodal/two_impact.h"

namespace nsmodal {
namespace {

// Targets of the orbit engine.
constexpr double kPeriodicityTarget = 1e-12;
constexpr double kRootTarget = 1e-10;

bool HasRootAwayFromHalf(const std::vector<double>& roots, double period) {
  for (double t2 : roots) {
    if (std::abs(t2 - period / 2) > 1e-6 * period) return true;
  }
  return false;
}

// Issue 10: the library switched GSL's process-wide error handler off. It is
// the application's: the root finders, the golden-section search and the
// simplex search of `explore` must run without reaching it and leave it set.
int gsl_errors = 0;
void CountingHandler(const char*, const char*, int, int) { ++gsl_errors; }

TEST(TwoImpact, LeavesGslErrorHandlerToTheApplication) {
  const AnalysisBasis b = testing::PaperBasis();
  gsl_error_handler_t* before = gsl_set_error_handler(&CountingHandler);
  for (double period = 1.0; period <= 12.0; period += 0.5) TwoImpactOrbits(b, period);
  OneImpactTransitions(b, 0.05, 40.0, 0.01);
  ExploreOptions explore;
  explore.impacts = 3;
  explore.grid = 12;
  ExploreImpacts(b, {27.5}, explore);
  EXPECT_EQ(gsl_set_error_handler(before), &CountingHandler);
  EXPECT_EQ(gsl_errors, 0);
}

TEST(TwoImpact, Figure6Classification) {
  // Fig. 6: no root t2 != T/2 for T in {1, 2, 7, 8, 10}; some for {3, 4, 5, 6, 9}.
  const AnalysisBasis b = testing::PaperBasis();
  for (int period : {1, 2, 7, 8, 10}) EXPECT_FALSE(HasRootAwayFromHalf(TwoImpactRoots(b, period), period)) << period;
  for (int period : {3, 4, 5, 6, 9}) EXPECT_TRUE(HasRootAwayFromHalf(TwoImpactRoots(b, period), period)) << period;
}

TEST(TwoImpact, Eq27ThresholdAlwaysHasARootAwayFromHalf) {
  const AnalysisBasis b = testing::PaperBasis();
  const double threshold = 1.5 * b.Periods().maxCoeff();  // 3 max(T1, T2) / 2
  EXPECT_NEAR(threshold, 15.28, 0.01);
  for (double period = threshold; period < 40.0; period += 0.37) {
    EXPECT_TRUE(HasRootAwayFromHalf(TwoImpactRoots(b, period), period)) << "T = " << period;
  }
}

TEST(TwoImpact, RootsAreRootsKernelHasDimensionTwoAndOrbitsArePeriodic) {
  // Eq. 28: det A_2 = 0 implies dim ker A_2 = 2.
  const AnalysisBasis b = testing::PaperBasis();
  int checked = 0;
  for (double period = 2.5; period < 30.0; period += 0.53) {
    for (const Orbit& o : TwoImpactOrbits(b, period)) {
      const double t2 = o.times[0];
      const Eigen::JacobiSVD<Eigen::MatrixXd> svd(MatrixA(b, {t2}, period));
      const Eigen::VectorXd s = svd.singularValues();
      // Smallest two singular values at round-off (a double eigenvalue 1 of an
      // orthogonal matrix), the next one of order one.
      EXPECT_LT(s[3], 1e-12) << "T = " << period << " t2 = " << t2;
      EXPECT_LT(s[2], 1e-12) << "T = " << period << " t2 = " << t2;
      EXPECT_GT(s[1], 1e-6) << "T = " << period << " t2 = " << t2;
      EXPECT_EQ(KernelDimension(MatrixA(b, {t2}, period), 1e-9), 2);
      if (o.potential) {
        EXPECT_LT(o.periodicity_residual, kPeriodicityTarget) << "T = " << period << " t2 = " << t2;
        EXPECT_LT(o.nc2_residual, kPeriodicityTarget);
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(TwoImpact, RootsDoNotMoveWhenTheGridIsRefined) {
  // The grid only brackets; the root is Brent's: a 10x finer grid gives the
  // same roots to the root target.
  const AnalysisBasis b = testing::PaperBasis();
  TwoImpactOptions fine;
  fine.t2_step = 0.001;
  for (double period : {3.0, 6.0, 9.0, 17.3, 33.1}) {
    const std::vector<double> coarse_roots = TwoImpactRoots(b, period);
    const std::vector<double> fine_roots = TwoImpactRoots(b, period, fine);
    ASSERT_EQ(coarse_roots.size(), fine_roots.size()) << "T = " << period;
    for (std::size_t k = 0; k < coarse_roots.size(); ++k) EXPECT_NEAR(coarse_roots[k], fine_roots[k], kRootTarget);
  }
}

TEST(TwoImpact, SymmetryT2ToTMinusT2) {
  // Starting the same orbit at its second impact swaps the flight times.
  const AnalysisBasis b = testing::PaperBasis();
  for (double period : {3.0, 6.0, 9.0, 21.7}) {
    const std::vector<Orbit> orbits = TwoImpactOrbits(b, period);
    for (const Orbit& o : orbits) {
      const Orbit* mirror = nullptr;
      for (const Orbit& p : orbits) {
        if (std::abs(p.times[0] - (period - o.times[0])) < kRootTarget) mirror = &p;
      }
      ASSERT_NE(mirror, nullptr) << "T = " << period << " t2 = " << o.times[0];
      EXPECT_NEAR(mirror->energy, o.energy, 1e-10 * o.energy);
      EXPECT_EQ(mirror->admissible, o.admissible);
    }
  }
}

TEST(TwoImpact, HalfPeriodRootIsTheOneImpactOrbitRunTwice) {
  const AnalysisBasis b = testing::PaperBasis();
  for (double period : {3.0, 7.0, 12.0}) {
    const Orbit two = TwoImpactOrbitAt(b, period / 2, period);
    EXPECT_TRUE(two.potential);
    EXPECT_FALSE(two.degenerate);
    // The 1-ipp orbit of period T/2 (one_impact.h closed form) has the same state.
    Eigen::VectorXd y(4);
    const double h = 0.5 * period / 2;
    const double scale = b.gap / [&] {
      double d = 0.0;
      for (int i = 0; i < 2; ++i) d += b.r[i] * b.r[i] / (std::tan(b.omega[i] * h) * b.omega[i]);
      return d;
    }();
    for (int i = 0; i < 2; ++i) {
      y[i] = scale * b.r[i] / std::tan(b.omega[i] * h);
      y[2 + i] = scale * b.r[i];
    }
    EXPECT_LT((two.y0 - y).norm(), 1e-10 * y.norm()) << "T = " << period;
  }
}

TEST(TwoImpact, ContinuationFollowsTheRootCurveThroughItsFoldsAndAgreesWithTheGrid) {
  // The branch through the 3 T_1 linear mode (paper Figs. 11-12): from
  // (t2, T) = (2.87, 8.866) the curve turns back at T ~ 8.615 and again at
  // T ~ 9.181. A grid in T sees each fold only as two roots merging.
  const AnalysisBasis b = testing::PaperBasis();
  double t2 = 0.0;
  for (double r : TwoImpactRoots(b, 8.866)) {
    if (std::abs(r - 2.87) < 0.01) t2 = r;
  }
  ASSERT_GT(t2, 0.0);
  BranchOptions opt;
  opt.step = 0.02;
  opt.period_min = 8.0;
  opt.period_max = 9.6;
  const std::vector<BranchPoint> branch = TwoImpactBranch(b, t2, 8.866, opt);
  ASSERT_GT(branch.size(), 100u);
  // Every 10th point is a root that the grid search finds at that T too.
  for (std::size_t k = 0; k < branch.size(); k += 10) {
    double nearest = INFINITY;
    for (double r : TwoImpactRoots(b, branch[k].period)) nearest = std::min(nearest, std::abs(r - branch[k].t2));
    EXPECT_LT(nearest, kRootTarget) << "t2 = " << branch[k].t2 << " T = " << branch[k].period;
  }
  // Steps are the asked arclength (Newton's correction is orthogonal to the
  // predictor, so the chord is at least the step and not much more).
  for (std::size_t k = 1; k < branch.size(); ++k) {
    const double chord = std::hypot(branch[k].t2 - branch[k - 1].t2, branch[k].period - branch[k - 1].period);
    EXPECT_GE(chord, opt.step * (1 - 1e-9));
    EXPECT_LT(chord, 1.1 * opt.step);
  }
  // The fold below: T has an interior minimum along the branch near 8.615,
  // with the curve continuing on both sides of it.
  std::size_t fold = 0;
  for (std::size_t k = 0; k < branch.size(); ++k) {
    if (branch[k].t2 < 3.0 && branch[k].period < branch[fold].period) fold = k;
  }
  ASSERT_GT(fold, 10u);
  ASSERT_LT(fold + 10, branch.size());
  EXPECT_NEAR(branch[fold].period, 8.615, 0.005);
  EXPECT_GT(branch[fold - 10].period, branch[fold].period);
  EXPECT_GT(branch[fold + 10].period, branch[fold].period);
  // Below the fold the grid has no root near it; just above, two.
  auto count_near = [&](double period) {
    int n = 0;
    for (double r : TwoImpactRoots(b, period)) n += std::abs(r - branch[fold].t2) < 0.5;
    return n;
  };
  EXPECT_EQ(count_near(branch[fold].period - 0.01), 0);
  EXPECT_EQ(count_near(branch[fold].period + 0.01), 2);
}

TEST(TwoImpact, ContinuationRefusesAStartThatIsNotARoot) {
  const AnalysisBasis b = testing::PaperBasis();
  EXPECT_THROW(TwoImpactBranch(b, 1.0, 8.0), InputError);
}

}  // namespace
}  // namespace nsmodal
