#include <gtest/gtest.h>

#include <random>

#include "fixtures.h"
#include "nsmodal/return_map.h"

namespace nsmodal {
namespace {

// Products of a few orthogonal 4x4 matrices: round-off ~1e-15.
constexpr double kOrthoTol = 1e-13;

TEST(Pfaffian, SquaresToDeterminantAndMatches4x4Formula) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int n : {2, 4, 6, 8}) {
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) {
        a(i, j) = u(rng);
        a(j, i) = -a(i, j);
      }
    const double pf = Pfaffian(a);
    EXPECT_NEAR(pf * pf, a.determinant(), 1e-12 * std::max(1.0, std::abs(a.determinant())));
    if (n == 4) {
      EXPECT_NEAR(pf, a(0, 1) * a(2, 3) - a(0, 2) * a(1, 3) + a(0, 3) * a(1, 2), 1e-14);
    }
  }
}

TEST(ReturnMap, OrthogonalWithDeterminantMinusOneToTheM) {
  const AnalysisBasis b = testing::PaperBasis();
  const std::vector<std::vector<double>> impact_times{{}, {1.3}, {1.3, 2.2}, {0.4, 1.3, 2.9}};
  for (const auto& times : impact_times) {
    const Eigen::MatrixXd q = ReturnMap(b, times, 4.1);
    EXPECT_TRUE((q.transpose() * q).isIdentity(kOrthoTol));
    EXPECT_NEAR(q.determinant(), times.size() % 2 == 0 ? -1.0 : 1.0, kOrthoTol);
  }
}

TEST(ReturnMap, KernelOfA1HasDimensionOne) {
  const AnalysisBasis b = testing::PaperBasis();
  for (double t = 0.3; t < 40.0; t += 0.77) EXPECT_EQ(KernelDimension(MatrixA(b, {}, t), 1e-9), 1) << "T = " << t;
}

TEST(ReturnMap, DetA2IsNonNegativeAndVanishesAtHalfPeriod) {
  // Eq. 26: det A_2(T/2, T) = 0 for every T; det A_2 >= 0 everywhere (double roots).
  const AnalysisBasis b = testing::PaperBasis();
  for (double period = 0.5; period < 40.0; period += 0.61) {
    EXPECT_NEAR(MatrixA(b, {period / 2}, period).determinant(), 0.0, 1e-13) << "T = " << period;
    for (double s = 0.05; s < 1.0; s += 0.1) EXPECT_GE(MatrixA(b, {s * period}, period).determinant(), -1e-14);
  }
}

TEST(ReturnMap, IndicatorSquaredIsDetQMinusIPlusTimesDetQPlusI) {
  const AnalysisBasis b = testing::PaperBasis();
  for (double t2 : {0.3, 1.1, 2.5}) {
    const Eigen::MatrixXd q = ReturnMap(b, {t2}, 3.7);
    const Eigen::MatrixXd id = Eigen::MatrixXd::Identity(4, 4);
    const double f = TwoImpactIndicator(b, t2, 3.7);
    EXPECT_NEAR(f * f, (q - id).determinant() * (q + id).determinant(), 1e-12);
  }
}

}  // namespace
}  // namespace nsmodal
