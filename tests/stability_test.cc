#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

#include "fixtures.h"
#include "nsmodal/model.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/roots.h"
#include "nsmodal/stability.h"
#include "nsmodal/transitions.h"

namespace nsmodal {
namespace {

AnalysisBasis UnitChain(int n) {
  return AnalysisBasis(MakeChain(std::vector<double>(n, 1.0), std::vector<double>(n, 1.0), n - 1, 1.0, 1.0));
}

// Distance from mu to the nearest eigenvalue of the dense monodromy.
double NearestDense(const Eigen::VectorXcd& dense, std::complex<double> mu) {
  double d = INFINITY;
  for (int k = 0; k < dense.size(); ++k) d = std::min(d, std::abs(dense[k] - mu));
  return d;
}

// The structured 1-ipp spectrum (Gt, stability.h) against the eigenvalues of
// the dense monodromy (products of flows and saltation matrices, an
// independent route) on chains of 2, 10 and 50 masses and the paper's system.
// Tolerances: a simple eigenvalue of the non-normal M is computed by the dense
// solver to ~eps times its condition number (measured <= 1e-10 here); the
// trivial pair at 1 is a Jordan block there, split to ~sqrt(eps) = 1e-8, hence
// 1e-6 for the multipliers near 1; max_modulus and the verdict must agree to
// the same 1e-6 (the verdict's own tolerance).
TEST(Stability, StructuredOneImpactSpectrumIsTheDenseMonodromys) {
  const std::vector<AnalysisBasis> bases{testing::PaperBasis(), UnitChain(2), UnitChain(10), UnitChain(50)};
  int compared = 0, unstable = 0, complex_pairs = 0;
  for (const AnalysisBasis& b : bases) {
    for (double period = 0.73; period < 40.0; period += 0.61) {
      const Orbit o = OneImpactOrbit(b, period);
      if (!o.potential) continue;
      const Stability s = OrbitStability(b, o);
      if (!s.defined) continue;
      EXPECT_FALSE(s.dense_fallback) << "N = " << b.n << " T = " << period;
      ASSERT_EQ(s.multipliers.size(), 2 * b.n);
      const Eigen::VectorXcd dense = Monodromy(b, o).eigenvalues();
      for (int k = 0; k < s.multipliers.size(); ++k) {
        const double near_one = std::abs(s.multipliers[k] - 1.0) < 1e-4 ? 1e-6 : 1e-8;
        EXPECT_LT(NearestDense(dense, s.multipliers[k]), near_one)
            << "N = " << b.n << " T = " << period << " mu = " << s.multipliers[k];
      }
      const double dense_max = dense.cwiseAbs().maxCoeff();
      EXPECT_NEAR(s.max_modulus, dense_max, 1e-6 * dense_max) << "N = " << b.n << " T = " << period;
      if (std::abs(dense_max - 1.0) > 1e-5) {
        EXPECT_EQ(s.stable, dense_max <= 1.0 + 1e-6);
      }
      unstable += !s.stable;
      for (int k = 0; k < s.multipliers.size(); ++k) {
        complex_pairs += std::abs(s.multipliers[k]) > 1.0 + 1e-6 && std::abs(s.multipliers[k].imag()) > 1e-6;
      }
      ++compared;
    }
  }
  EXPECT_GT(compared, 150);
  EXPECT_GT(unstable, 20);      // both verdicts are exercised ...
  EXPECT_GT(complex_pairs, 0);  // ... and complex quadruplets off the circle
}

// The verdict-only mode (sweeps of large N) gives the same verdict, the same
// largest modulus and the same multipliers off the unit circle.
TEST(Stability, VerdictOnlyAgreesWithTheFullSpectrum) {
  const AnalysisBasis b = UnitChain(30);
  StabilityOptions verdict;
  verdict.all_multipliers = false;
  for (double period = 1.1; period < 30.0; period += 0.77) {
    const Orbit o = OneImpactOrbit(b, period);
    if (!o.potential) continue;
    const Stability full = OrbitStability(b, o), quick = OrbitStability(b, o, verdict);
    if (!full.defined) continue;
    EXPECT_EQ(quick.stable, full.stable) << "T = " << period;
    EXPECT_NEAR(quick.max_modulus, full.max_modulus, 1e-12 * full.max_modulus) << "T = " << period;
    EXPECT_EQ(quick.complete, quick.multipliers.size() == 2 * b.n) << "T = " << period;
    for (int k = 0; k < quick.multipliers.size(); ++k) {
      if (std::abs(std::abs(quick.multipliers[k]) - 1.0) < 1e-9) continue;
      EXPECT_LT(NearestDense(full.multipliers, quick.multipliers[k]), 1e-12) << "T = " << period;
    }
  }
}

// A larger chain, where most roots of Gt crowd among the poles: many complex
// pairs just off the axis, segments holding three real roots, pairs the
// sampling misses (the search must find and count each once). Against the
// dense monodromy: every multiplier off the circle is there, none twice, and
// no fallback. Tolerance 1e-8: the dense solver's accuracy on these simple
// eigenvalues (as above); 1 + 1e-6 is the verdict's own threshold, and a
// multiplier within 1e-4 of it on either side is not counted (the dense
// solver's error there is not the structured one's).
TEST(Stability, VerdictOnlyFindsEveryMultiplierOffTheCircleOfALargeChain) {
  const AnalysisBasis b = UnitChain(200);
  StabilityOptions verdict;
  verdict.all_multipliers = false;
  int checked = 0;
  for (double period : {5.3, 11.7, 23.9, 29.74, 37.1}) {  // 29.74: a root the signs miss, found by the search
    const Orbit o = OneImpactOrbit(b, period);
    if (!o.potential) continue;
    const Stability quick = OrbitStability(b, o, verdict);
    ASSERT_TRUE(quick.defined) << "T = " << period;
    EXPECT_FALSE(quick.dense_fallback) << "T = " << period;
    const Eigen::VectorXcd dense = Monodromy(b, o).eigenvalues();
    auto off = [](std::complex<double> mu) { return std::abs(mu) > 1.0 + 1e-6; };
    auto clear = [](std::complex<double> mu) { return std::abs(std::abs(mu) - 1.0 - 1e-6) > 1e-4; };
    int dense_off = 0, quick_off = 0;
    for (const std::complex<double>& mu : dense) dense_off += off(mu) && clear(mu);
    for (const std::complex<double>& mu : quick.multipliers) {
      if (!off(mu) || !clear(mu)) continue;
      ++quick_off;
      EXPECT_LT(NearestDense(dense, mu), 1e-8) << "T = " << period << " mu = " << mu;
    }
    EXPECT_EQ(quick_off, dense_off) << "T = " << period;
    EXPECT_GT(dense_off, 10) << "T = " << period;  // the case this test is for
    EXPECT_NEAR(quick.max_modulus, dense.cwiseAbs().maxCoeff(), 1e-8 * quick.max_modulus) << "T = " << period;
    ++checked;
  }
  EXPECT_GE(checked, 3);
}

// A mode that does not move the contact keeps its rotation: e^(+-i w3 T) are
// multipliers, and the others are the 2-dof system's.
TEST(Stability, UncoupledModeKeepsItsRotation) {
  const AnalysisBasis b2 = testing::PaperBasis();
  const AnalysisBasis b3(testing::PaperPlusUncoupledMass());
  for (double period : {5.0, 6.5, 9.2}) {
    const Stability s2 = OrbitStability(b2, OneImpactOrbit(b2, period));
    const Stability s3 = OrbitStability(b3, OneImpactOrbit(b3, period));
    EXPECT_EQ(s2.stable, s3.stable);
    EXPECT_NEAR(s2.max_modulus, s3.max_modulus, 1e-12 * s2.max_modulus);
    const double w3 = std::sqrt(5.0);
    EXPECT_LT(NearestDense(s3.multipliers, std::polar(1.0, w3 * period)), 1e-12);
    EXPECT_LT(NearestDense(s3.multipliers, std::polar(1.0, -w3 * period)), 1e-12);
  }
}

// +1 and -1 crossings are the zeros of Gt(2) and Gt(-2): at the paper's
// period doubling T* = 9.6211 = T_G / 2 (bridge_test), Gt(-2) changes sign.
TEST(Stability, SecularFunctionChangesSignAtAPeriodDoubling) {
  const AnalysisBasis b = testing::PaperBasis();
  const double ts = 9.6211;
  const double below = OneImpactSecularFunction(b, ts - 1e-3).Value(-2.0);
  const double above = OneImpactSecularFunction(b, ts + 1e-3).Value(-2.0);
  EXPECT_LT(below * above, 0.0);
}

// Issue 13: the stability changes of the paper's admissible 1-ipp family,
// located exactly. The values (6 decimals) to their last digit; each
// +1 crossing is where E(T) is extremal (Brent on a central difference of
// step 1e-6, whose error ~eps E / 1e-6 moves the root by < 1e-8), each -1
// crossing a sign change of det(M + I) of the dense monodromy 1e-7 either side.
TEST(Stability, MultiplierCrossingsOfThePaperAreLocatedExactly) {
  const AnalysisBasis b = testing::PaperBasis();
  std::vector<double> periods;
  std::vector<bool> admissible;
  for (int k = 0; k <= 3950; ++k) {
    periods.push_back(0.5 + 0.01 * k);
    admissible.push_back(OneImpactOrbit(b, periods.back()).admissible);
  }
  const std::vector<Transition> x = OneImpactMultiplierCrossings(b, periods, admissible);
  const std::vector<std::pair<double, TransitionKind>> expected{
      {5.721560, TransitionKind::kMultiplierPlusOne},  {7.285897, TransitionKind::kMultiplierMinusOne},
      {8.378589, TransitionKind::kMultiplierPlusOne},  {9.490667, TransitionKind::kMultiplierMinusOne},
      {9.621135, TransitionKind::kMultiplierMinusOne}, {20.177850, TransitionKind::kMultiplierPlusOne}};
  ASSERT_EQ(x.size(), expected.size());
  auto energy = [&](double t) { return OneImpactOrbit(b, t).energy; };
  auto slope = [&](double t) { return (energy(t + 1e-6) - energy(t - 1e-6)) / 2e-6; };
  auto det_plus_i = [&](double t) {
    const Eigen::MatrixXd m = Monodromy(b, OneImpactOrbit(b, t));
    return (m + Eigen::MatrixXd::Identity(m.rows(), m.cols())).determinant();
  };
  for (std::size_t k = 0; k < x.size(); ++k) {
    EXPECT_EQ(x[k].kind, expected[k].second) << k;
    EXPECT_NEAR(x[k].period, expected[k].first, 5e-7) << k;
    if (x[k].kind == TransitionKind::kMultiplierPlusOne) {
      EXPECT_NEAR(PolishRoot(slope, x[k].period - 1e-3, x[k].period + 1e-3), x[k].period, 1e-7);
    } else {
      EXPECT_LT(det_plus_i(x[k].period - 1e-7) * det_plus_i(x[k].period + 1e-7), 0.0) << x[k].period;
    }
  }
}

// One dof: the trivial pair is the whole spectrum. The dense path's reduced
// monodromy is then 0 x 0 (fuzz_scene found Eigen's eigenvalues of it binding
// a reference to null data under UBSan).
TEST(Stability, OneDofHasOnlyTheTrivialPair) {
  const AnalysisBasis b(MakeChain({1.0}, {1.0}, 0, 1.0, 1.0));
  const Orbit o = OneImpactOrbit(b, 3.0);
  ASSERT_TRUE(o.potential);
  const Stability s = OrbitStability(b, o);
  EXPECT_TRUE(s.defined);
  EXPECT_TRUE(s.stable);
  EXPECT_LE(s.max_modulus, 1.0 + 1e-12);
}

}  // namespace
}  // namespace nsmodal
