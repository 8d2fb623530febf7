#include <gtest/gtest.h>

#include <gsl/gsl_errno.h>

#include <algorithm>
#include <cmath>

#include "fixtures.h"
#include "nsmodal/error.h"
#include "nsmodal/model.h"
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

// det A_2 = det(S(T) - I) 4 P(t2)^2 (two_impact.h), on the paper's system and
// on a 10-mass chain: both sides computed independently (a dense determinant
// of the return map against the sum of sinusoids). The relative tolerance:
// det of a 2N x 2N matrix of O(1) entries loses ~N digits of eps at most.
TEST(TwoImpact, DeterminantOfA2IsTheSquareOfTheClosedFormIndicator) {
  for (int n : {2, 10}) {
    const AnalysisBasis b = n == 2 ? testing::PaperBasis()
                                   : AnalysisBasis(MakeChain(std::vector<double>(n, 1.0), std::vector<double>(n, 1.0),
                                                             n - 1, 1.0, 1.0));
    for (double period : {3.1, 7.3, 17.9}) {
      const SinusoidSum p = TwoImpactSignal(b, period);
      double det_s = 1.0;
      for (int i = 0; i < n; ++i) det_s *= 2.0 - 2.0 * std::cos(b.omega[i] * period);
      for (double t2 = 0.05 * period; t2 < period; t2 += 0.09 * period) {
        const double det_a = MatrixA(b, {t2}, period).determinant();
        const double closed = det_s * 4.0 * p.Position(t2) * p.Position(t2);
        EXPECT_NEAR(det_a, closed, 1e-11 * std::max(1.0, det_s)) << "N = " << n << " T = " << period << " t2 = " << t2;
      }
    }
  }
}

// The roots against an independent scan: the sign changes of the Pfaffian
// indicator F (return_map.h) on a grid of 1e-3, kept where sigma_min(A_2) is
// at round-off (F also changes sign at -1 crossings). Every root of the scan
// is a root of the closed form and back, to kRootTarget (Brent on F brackets
// to ~1e-15; the closed form's roots are Brent's too).
TEST(TwoImpact, RootsAreThoseOfAnIndependentPfaffianScan) {
  const AnalysisBasis b = testing::PaperBasis();
  for (double period : {3.0, 6.0, 9.0, 17.3, 33.1}) {
    std::vector<double> scan{0.5 * period};
    const int cells = static_cast<int>(std::ceil(period / 1e-3));
    double prev = TwoImpactIndicator(b, 0.0, period);
    for (int j = 1; j <= cells; ++j) {
      const double lo = period * (j - 1) / cells, hi = period * j / cells;
      const double f = TwoImpactIndicator(b, hi, period);
      if ((prev < 0.0) != (f < 0.0) && j > 1 && j < cells) {
        double a = lo, c = hi, fa = prev;
        for (int it = 0; it < 200 && c - a > 1e-15 * period; ++it) {
          const double m = 0.5 * (a + c), fm = TwoImpactIndicator(b, m, period);
          if ((fm < 0.0) == (fa < 0.0)) {
            a = m;
            fa = fm;
          } else {
            c = m;
          }
        }
        const double root = 0.5 * (a + c);
        const double sigma = Eigen::JacobiSVD<Eigen::MatrixXd>(MatrixA(b, {root}, period)).singularValues().minCoeff();
        if (sigma < 1e-9 && std::abs(root - 0.5 * period) > 1e-9 * period) scan.push_back(root);
      }
      prev = f;
    }
    std::sort(scan.begin(), scan.end());
    const std::vector<double> roots = TwoImpactRoots(b, period);
    ASSERT_EQ(roots.size(), scan.size()) << "T = " << period;
    for (std::size_t k = 0; k < roots.size(); ++k) EXPECT_NEAR(roots[k], scan[k], kRootTarget) << "T = " << period;
  }
}

// A 10-mass chain: every root gives an orbit whose A_2 has a kernel of
// dimension 2 (eq. 28) and that is periodic to the engine's target.
TEST(TwoImpact, ChainOfTenMassesRootsHaveTwoDimensionalKernels) {
  const AnalysisBasis b(MakeChain(std::vector<double>(10, 1.0), std::vector<double>(10, 1.0), 9, 1.0, 1.0));
  int potential = 0;
  for (double period : {4.1, 11.7, 25.3}) {
    for (const Orbit& o : TwoImpactOrbits(b, period)) {
      EXPECT_EQ(KernelDimension(MatrixA(b, o.times, period), 1e-9), 2) << "T = " << period << " t2 = " << o.times[0];
      if (o.potential) {
        ++potential;
        EXPECT_LT(o.periodicity_residual, kPeriodicityTarget) << "T = " << period << " t2 = " << o.times[0];
      }
    }
  }
  EXPECT_GT(potential, 10);
}

TEST(TwoImpact, PeriodMultipleOfALinearPeriodHasNoRoots) {
  const AnalysisBasis b = testing::PaperBasis();
  const double t1 = b.Periods()[1];
  // w_1 T / 2 = 2 pi to round-off: S(T) - I is singular, no orbit (as for 1 impact).
  EXPECT_EQ(TwoImpactSignal(b, 2.0 * t1).omega.size(), 0);
  EXPECT_TRUE(TwoImpactRoots(b, 2.0 * t1).empty());
  // 1e-6 away the indicator exists again and T/2 is a root.
  EXPECT_FALSE(TwoImpactRoots(b, 2.0 * t1 + 1e-6).empty());
}

// Within 2e-4 of a multiple of T1 (5 T1 = 14.8598, 6 T1, 10 T1) the
// closed-form kernel divides by sin(w_1 T / 2) ~ 1e-3 and was periodic to
// 5e-12 only (two of the orbits at T = 14.86, above the engine's target);
// past the target the orbit is taken from the SVD kernel of A_2 instead.
TEST(TwoImpact, OrbitsNearAMultipleOfALinearPeriodMeetThePeriodicityTarget) {
  const AnalysisBasis b(PaperModel());
  for (double period : {14.86, 17.83, 29.72}) {
    const std::vector<Orbit> orbits = TwoImpactOrbits(b, period);
    ASSERT_FALSE(orbits.empty()) << period;
    for (const Orbit& o : orbits) {
      EXPECT_LT(o.periodicity_residual, kPeriodicityTarget) << period << " t2 = " << o.times[0];
      EXPECT_LT(o.nc2_residual, kPeriodicityTarget) << period << " t2 = " << o.times[0];
    }
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
