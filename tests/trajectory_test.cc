#include <gtest/gtest.h>

#include "fixtures.h"
#include "nsmodal/flow.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/trajectory.h"
#include "nsmodal/two_impact.h"

namespace nsmodal {
namespace {

// Closed-form states from O(1) orthogonal maps: a few ulp (see bridge_test).
constexpr double kRoundOff = 1e-12;

TEST(Trajectory, ClosesOnItselfWithTheImpactsAsVelocityJumps) {
  const AnalysisBasis b = testing::PaperBasis();
  int checked = 0;
  for (const Orbit& o : TwoImpactOrbits(b, 9.0)) {
    if (!o.admissible) continue;
    ++checked;
    const int samples = 50;
    const Eigen::MatrixXd tr = OrbitTrajectory(b, o, samples);
    ASSERT_EQ(tr.rows(), 2 * (samples + 1));
    EXPECT_EQ(tr(0, 0), 0.0);
    EXPECT_EQ(tr(tr.rows() - 1, 0), o.period);
    // Starts at z0; at T the positions are back and the velocities await the impact.
    EXPECT_LT((tr.row(0).tail(4).transpose() - o.z0).norm(), kRoundOff);
    EXPECT_LT((tr.row(tr.rows() - 1).segment(1, 2).transpose() - o.z0.head(2)).norm(), kRoundOff);
    // The impact at t2: same time and position twice, v_c reversed (e = 1).
    const long k = samples;
    EXPECT_EQ(tr(k, 0), tr(k + 1, 0));
    EXPECT_NEAR(tr(k, 2), b.gap, kRoundOff);
    EXPECT_NEAR(tr(k + 1, 4), -tr(k, 4), kRoundOff);
    EXPECT_GT(tr(k, 4), 0.0);
    EXPECT_LE(tr.col(2).maxCoeff(), b.gap + kRoundOff);  // admissible: x_2 <= d
  }
  EXPECT_EQ(checked, 2);  // t2 and T - t2 (bridge_test: roots at T = 9)
}

TEST(Trajectory, ShiftedByHalfAPeriodItIsTheSameClosedCurveFromItsMidpoint) {
  const AnalysisBasis b = testing::PaperBasis();
  const Orbit o = OneImpactOrbit(b, 7.5);
  const Eigen::MatrixXd tr = OrbitTrajectory(b, o, 40);  // T/2 is sample 20
  const Eigen::MatrixXd half = ShiftTrajectory(tr, 0.5 * o.period, o.period);
  ASSERT_EQ(half.rows(), tr.rows() + 1);  // the midpoint both starts and ends it
  // It starts and ends where the orbit is at T/2, and time runs from 0 to T.
  Eigen::VectorXd y = o.y0;
  Flow(b, 0.5 * o.period, y);
  EXPECT_LT((half.row(0).tail(4).transpose() - PhysicalOf(b, y)).norm(), kRoundOff);
  EXPECT_LT((half.row(half.rows() - 1).tail(4).transpose() - PhysicalOf(b, y)).norm(), kRoundOff);
  EXPECT_EQ(half(0, 0), 0.0);
  EXPECT_EQ(half(half.rows() - 1, 0), o.period);
  for (long i = 1; i < half.rows(); ++i) EXPECT_GE(half(i, 0), half(i - 1, 0));
  // The impact is now at T/2: before it v_c > 0, after it reversed.
  const long k = 20;  // rows 20..40 of the original come first
  EXPECT_EQ(half(k, 0), 0.5 * o.period);
  EXPECT_EQ(half(k + 1, 0), 0.5 * o.period);
  EXPECT_GT(half(k, 4), 0.0);
  EXPECT_NEAR(half(k + 1, 4), -half(k, 4), kRoundOff);
  // Shifting again by T/2 splits that impact: after-impact state first.
  const Eigen::MatrixXd back = ShiftTrajectory(half, 0.5 * o.period, o.period);
  EXPECT_LT((back.row(0) - tr.row(0)).norm(), kRoundOff);
  EXPECT_LT((back.row(back.rows() - 1) - tr.row(tr.rows() - 1)).norm(), kRoundOff);
}

}  // namespace
}  // namespace nsmodal
