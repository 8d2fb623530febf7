#include <gtest/gtest.h>

#include <cmath>

#include "fixtures.h"
#include "nsmodal/flow.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/transitions.h"

namespace nsmodal {
namespace {

// Target of the orbit engine: |z(T) - z(0)| <= 1e-12 |z(0)|.
constexpr double kPeriodicityTarget = 1e-12;

// Eq. 21-22 exactly as printed, with P the matrix of eigenvectors of M^-1 K
// (columns) of the 2-dof chain, optionally with cot(w T / 2) in A(T).
double PaperEq21(double period, double t, bool half_angle, bool flip_b2 = false) {
  const Model m = PaperModel();
  Eigen::EigenSolver<Eigen::MatrixXd> es(m.mass.inverse() * m.stiffness);
  Eigen::Vector2d w2 = es.eigenvalues().real();
  Eigen::Matrix2d p = es.eigenvectors().real();
  if (w2[0] > w2[1]) {
    std::swap(w2[0], w2[1]);
    p.col(0).swap(p.col(1));
  }
  const double w1 = std::sqrt(w2[0]), w2s = std::sqrt(w2[1]);
  auto cot = [&](double x) { return half_angle ? 1.0 / std::tan(x / 2) : 1.0 / std::tan(x); };
  const double a = m.FirstContact().gap / (w2s * p(0, 1) * p(1, 0) * cot(w1 * period) - w1 * p(0, 0) * p(1, 1) * cot(w2s * period));
  const double b1 = p(0, 1) * p(1, 0) * w2s / std::sin(w1 * period / 2);
  const double b2 = (flip_b2 ? -1.0 : 1.0) * p(0, 0) * p(1, 1) * w1 / std::sin(w2s * period / 2);
  return a * (b1 * std::cos(w1 * (t - period / 2)) + b2 * std::cos(w2s * (t - period / 2)));
}

TEST(OneImpact, ClosedFormEqualsKernelOfA1) {
  const AnalysisBasis b = testing::PaperBasis();
  for (double period = 0.2; period < 40.0; period += 0.123) {
    const Orbit closed = OneImpactOrbit(b, period);
    const Orbit kernel = OneImpactOrbitFromKernel(b, period);
    // The SVD kernel of an orthogonal-minus-identity matrix is accurate to
    // ~eps / gap of singular values; relative 1e-10 covers the periods close to
    // T = k T_i where that gap closes.
    EXPECT_LT((closed.z0 - kernel.z0).norm(), 1e-10 * closed.z0.norm()) << "T = " << period;
  }
}

TEST(OneImpact, GeneralFormOfEq21MatchesKernel) {
  const AnalysisBasis b = testing::PaperBasis();
  for (double period : {1.3, 4.0, 7.7, 12.5, 23.0}) {
    const Orbit o = OneImpactOrbitFromKernel(b, period);
    for (double s : {0.1, 0.3, 0.5, 0.8}) {
      Eigen::VectorXd y = o.y0;
      Flow(b, s * period, y);
      EXPECT_NEAR(OneImpactContactPosition(b, period, s * period), ContactPosition(b, y),
                  1e-10 * std::max(1.0, std::abs(ContactPosition(b, y))));
    }
  }
}

TEST(OneImpact, PaperEq22HoldsWithHalfAngleCotangentAndSignOfB2) {
  // Eqs. 21-22 as printed disagree with the kernel of A_1; they agree once
  // A(T) uses cot(w_i T / 2) instead of cot(w_i T) and B2 takes the opposite
  // sign (with P the eigenvectors of M^-1 K in columns). The tolerance is the
  // round-off of the two formulas at O(1) amplitudes.
  const AnalysisBasis b = testing::PaperBasis();
  for (double period : {1.3, 4.0, 7.7, 12.5, 23.0}) {
    for (double s : {0.1, 0.3, 0.5}) {
      const double ref = OneImpactContactPosition(b, period, s * period);
      EXPECT_GT(std::abs(PaperEq21(period, s * period, false, false) - ref), 1e-3) << "T = " << period;
      EXPECT_NEAR(PaperEq21(period, s * period, true, true), ref, 1e-10 * std::max(1.0, std::abs(ref)));
    }
  }
}

TEST(OneImpact, PeriodicEnergyConservingAndOnTheObstacle) {
  const AnalysisBasis b = testing::PaperBasis();
  double worst = 0.0;
  for (double period = 0.05; period < 40.0; period += 0.0137) {
    const Orbit o = OneImpactOrbit(b, period);
    if (!o.potential) continue;
    worst = std::max(worst, o.periodicity_residual);
    EXPECT_LT(o.nc2_residual, 1e-12) << "T = " << period;
    // Energy is conserved through flight and the elastic impact.
    Eigen::VectorXd y = o.y0;
    Flow(b, period, y);
    Impact(b, 1.0, y);
    EXPECT_NEAR(Energy(b, y), o.energy, 1e-12 * o.energy);
  }
  EXPECT_LT(worst, kPeriodicityTarget);
}

TEST(OneImpact, ExactNc3AgreesWithDenseSampling) {
  // Sampling at 2e5 points over a period can only under-estimate the maximum;
  // the exact check must never report admissible where sampling sees x_c > d.
  const AnalysisBasis b = testing::PaperBasis();
  for (double period = 0.5; period < 30.0; period += 0.29) {
    const Orbit o = OneImpactOrbit(b, period);
    const ContactSignal f(b, o.y0);
    // On [a, b] inside the flight, the maximum of x_c is at an interior critical
    // point or at a or b: the exact maximum can only be above the sampled one.
    const double a = 0.01 * period, bb = 0.99 * period;
    double sampled = -1e300;
    for (int k = 0; k <= 200000; ++k) sampled = std::max(sampled, f.Position(a + (bb - a) * k / 200000.0) - b.gap);
    const double exact = std::max({o.max_excess, f.Position(a) - b.gap, f.Position(bb) - b.gap});
    EXPECT_GE(exact, sampled - 1e-12) << "T = " << period;
    // Excursions larger than the sampling resolution (|f''| h^2 / 8) are seen by both.
    const double h = (bb - a) / 200000.0;
    if (sampled > f.bound[2] * h * h) {
      EXPECT_FALSE(o.admissible) << "T = " << period;
    }
  }
}

TEST(OneImpact, ExactNc3CatchesAShortExcursionThatCoarseSamplingMisses) {
  // Near a grazing transition the excursion above d is tiny and short; find a
  // period just past the first grazing transition of the paper's system.
  const AnalysisBasis b = testing::PaperBasis();
  const std::vector<Transition> tr = OneImpactTransitions(b, 9.0, 9.3, 0.01);
  ASSERT_FALSE(tr.empty());
  const double tg = tr.front().period;
  ASSERT_EQ(tr.front().kind, TransitionKind::kGrazing);
  const bool adm_below = OneImpactOrbit(b, tg - 1e-6).admissible;
  const double t_bad = adm_below ? tg + 1e-6 : tg - 1e-6;
  const Orbit o = OneImpactOrbit(b, t_bad);
  EXPECT_FALSE(o.admissible);
  EXPECT_GT(o.max_excess, 0.0);
  EXPECT_LT(o.max_excess, 1e-4);
  const ContactSignal f(b, o.y0);
  double sampled = -1e300;
  for (int k = 1; k < 100; ++k) sampled = std::max(sampled, f.Position(t_bad * k / 100.0) - b.gap);
  EXPECT_LT(sampled, 0.0) << "100 samples already see it: the test no longer shows what sampling misses";
}

}  // namespace
}  // namespace nsmodal
