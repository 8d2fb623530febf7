#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "fixtures.h"
#include "nsmodal/flow.h"
#include "nsmodal/roots.h"

namespace nsmodal {
namespace {

// The matrix exponential (scaling and squaring) of an O(1) matrix at t <= 10
// is accurate to ~1e-13; the modal flow is exact up to cos/sin round-off.
constexpr double kTol = 1e-11;

TEST(Flow, MatchesMatrixExponential) {
  const Model m = testing::CoupledThreeDof();
  const AnalysisBasis b(m);
  Eigen::VectorXd z(6);
  z << 0.2, -0.1, 0.3, 0.5, -1.0, 0.25;
  for (double t : {0.1, 1.7, 9.3}) {
    Eigen::VectorXd y = ToModal(b, z.head(3), z.tail(3));
    Flow(b, t, y);
    const Eigen::VectorXd expect = testing::PhysicalFlow(m, t) * z;
    EXPECT_LT((PhysicalOf(b, y) - expect).norm(), kTol * expect.norm()) << "t = " << t;
    EXPECT_TRUE(FlowMatrix(b, t).isApprox(FlowMatrix(b, t), 0.0));
  }
}

TEST(Flow, ImpactLawFlipsContactVelocityAndConservesEnergyWhenElastic) {
  const Model m = testing::CoupledThreeDof();  // non-diagonal M
  const AnalysisBasis b(m);
  Eigen::VectorXd x(3), v(3);
  x << 0.1, 0.7, -0.2;
  v << 0.3, 1.2, -0.5;
  for (double e : {0.0, 0.5, 1.0}) {
    Eigen::VectorXd y = ToModal(b, x, v);
    const double e0 = Energy(b, y);
    Impact(b, e, y);
    const Eigen::VectorXd v_after = VelocityOf(b, y);
    EXPECT_NEAR(v_after[1], -e * v[1], 1e-14);
    // The impulse acts along the contact normal: M (v+ - v-) is parallel to e_c.
    const Eigen::VectorXd impulse = m.mass * (v_after - v);
    EXPECT_NEAR(impulse[0], 0.0, 1e-14);
    EXPECT_NEAR(impulse[2], 0.0, 1e-14);
    EXPECT_TRUE(PositionOf(b, y).isApprox(x, 1e-14));
    if (e == 1.0) {
      EXPECT_NEAR(Energy(b, y), e0, 1e-14 * e0);
    } else {
      EXPECT_LT(Energy(b, y), e0);
    }
  }
}

TEST(Flow, ContactSignalMatchesFlowAndItsBounds) {
  const AnalysisBasis b = testing::PaperBasis();
  const Eigen::VectorXd y = Eigen::Vector4d(0.3, -1.1, 0.8, 0.4);
  const ContactSignal f(b, y);
  for (double t = 0.0; t < 20.0; t += 0.37) {
    Eigen::VectorXd yt = FlowMatrix(b, t) * y;
    EXPECT_NEAR(f.Position(t), ContactPosition(b, yt), 1e-14);
    EXPECT_NEAR(f.Velocity(t), ContactVelocity(b, yt), 1e-14);
    EXPECT_LE(std::abs(f.Acceleration(t)), f.bound[2]);
    EXPECT_DOUBLE_EQ(f.VelocityAcceleration(t).first, f.Velocity(t));
  }
}

// The derivative bounds sum_i w_i^k sqrt(a_i^2 + b_i^2) come from a square
// root of a_i^2 + b_i^2, vectorised; amplitudes whose squares would underflow
// (1e-200) or overflow (1e200) must still come out right (std::hypot then).
// Expected values exact to a few ulps: 4e-16 relative.
TEST(Flow, SinusoidBoundsSurviveTinyAndHugeAmplitudes) {
  for (const double scale : {1.0, 1e-200, 1e200}) {
    const SinusoidSum f(0.0, Eigen::Vector2d(3.0 * scale, 0.0), Eigen::Vector2d(4.0 * scale, 2.0 * scale),
                        Eigen::Vector2d(1.0, 2.0));
    EXPECT_NEAR(f.bound[0], 7.0 * scale, 4e-16 * 7.0 * scale) << scale;   // 5 + 2
    EXPECT_NEAR(f.bound[2], 13.0 * scale, 4e-16 * 13.0 * scale) << scale;  // 5 + 4 * 2
    EXPECT_NEAR(f.bound[6], 133.0 * scale, 4e-16 * 133.0 * scale) << scale;  // 5 + 64 * 2
  }
}

// Issue 14: every searching loop has a bound and says when it hit it. The
// root isolation of NC3 stops at its cell budget and reports it; with the
// budget the caller derives from the scales it completes.
TEST(Roots, IsolationStopsAtItsWorkLimitAndSaysSo) {
  // sin(50 t) on [0, 10]: roots k pi / 50 for k = 0..159 (t = 0 included), 160.
  auto g = [](double t) { return std::pair<double, double>{std::sin(50.0 * t), 50.0 * std::cos(50.0 * t)}; };
  bool complete = true;
  const std::vector<double> few = IsolateRoots(g, 50.0, 2500.0, 0.0, 10.0, 1e-12, 20, &complete);
  EXPECT_FALSE(complete);
  EXPECT_LT(few.size(), 160u);
  const std::vector<double> all = IsolateRoots(g, 50.0, 2500.0, 0.0, 10.0, 1e-12, 1000 * (2 + 500 / 3), &complete);
  EXPECT_TRUE(complete);
  EXPECT_EQ(all.size(), 160u);
}

}  // namespace
}  // namespace nsmodal
