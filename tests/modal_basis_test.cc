#include <gtest/gtest.h>

#include "fixtures.h"
#include "nsmodal/flow.h"
#include "nsmodal/error.h"
#include "nsmodal/modal_basis.h"

namespace nsmodal {
namespace {

// Eigen-solver round-off on O(1) matrices.
constexpr double kTol = 1e-12;

TEST(ModalBasis, LinearPeriodsOfThePaper) {
  const AnalysisBasis b = testing::PaperBasis();
  // The paper prints T1 ~ 2.97 and T2 ~ 10.19 (two decimals): ours is the
  // first mode in the paper's naming when sorted by period, descending.
  const Eigen::VectorXd t = b.Periods();
  EXPECT_NEAR(t[1], 2.97, 0.005);
  EXPECT_NEAR(t[0], 10.19, 0.005);
}

// Issue 10: the library computed "admissible periodic orbits" for e = 0.5;
// the analysis basis cannot be built for e != 1, and says which field.
TEST(AnalysisBasis, RefusesARestitutionBelowOne) {
  Model m = PaperModel();
  m.FirstContact().restitution = 0.5;
  try {
    const AnalysisBasis b(m);
    FAIL() << "built an analysis basis for e = 0.5";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "system.restitution");
  }
  EXPECT_EQ(MakeModalBasis(m).n, 2);  // the simulator's basis takes any e
}

// Issue 14: --period 1e15 hung, 1e-320 exhausted memory, 1e-300 gave an
// "admissible" orbit with multipliers 3.7e284: periods outside 1e-6 to 1e5
// times the shortest linear period are refused, naming the field.
TEST(AnalysisBasis, RefusesPeriodsOutsideTheHonouredRange) {
  const AnalysisBasis b = testing::PaperBasis();
  const double shortest = b.Periods().minCoeff();
  for (double period : {1e15, 1e-320, 1e-300, 0.5e-6 * shortest, 2e5 * shortest}) {
    EXPECT_THROW(b.CheckPeriod(period, "--period"), InputError) << period;
  }
  EXPECT_NO_THROW(b.CheckPeriod(2e-6 * shortest));
  EXPECT_NO_THROW(b.CheckPeriod(0.5e5 * shortest));
  try {
    b.CheckPeriod(1e15, "--period");
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--period");
  }
}

TEST(ModalBasis, MassOrthonormalAndRoundTrip) {
  const Model m = testing::CoupledThreeDof();
  const AnalysisBasis b(m);
  EXPECT_TRUE((b.phi.transpose() * m.mass * b.phi).isIdentity(kTol));
  EXPECT_TRUE((b.phi.transpose() * m.stiffness * b.phi).isApprox(Eigen::MatrixXd(b.omega.cwiseAbs2().asDiagonal()),
                                                                 kTol));
  Eigen::VectorXd x(3), v(3);
  x << 0.1, -0.4, 0.3;
  v << 1.0, 0.5, -2.0;
  const Eigen::VectorXd y = ToModal(b, x, v);
  EXPECT_TRUE(PositionOf(b, y).isApprox(x, kTol));
  EXPECT_TRUE(VelocityOf(b, y).isApprox(v, kTol));
  // E = v'Mv/2 + x'Kx/2 = |y|^2/2.
  EXPECT_NEAR(Energy(b, y), 0.5 * v.dot(m.mass * v) + 0.5 * x.dot(m.stiffness * x), kTol);
}

}  // namespace
}  // namespace nsmodal
