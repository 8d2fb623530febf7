#include <gtest/gtest.h>

#include "fixtures.h"
#include "nsmodal/error.h"
#include "nsmodal/explore.h"

namespace nsmodal {
namespace {

TEST(Explore, ThreeImpactsKernelDimensionOneAndTheRepeatedOrbitIsFound) {
  // Section 2.3: odd m gives dim ker A_m = 1 (Q_m orthogonal with det -1).
  const AnalysisBasis b = testing::PaperBasis();
  ExploreOptions opt;
  opt.impacts = 3;
  opt.grid = 12;
  const ExploreReport r = ExploreImpacts(b, {4.0, 7.5}, opt);
  ASSERT_EQ(r.kernel_dimension_histogram.size(), 1u);
  EXPECT_EQ(r.kernel_dimension_histogram.begin()->first, 1);
  // The 1-ipp orbit of period T/3 run three times is always potential.
  bool repeated = false;
  for (const ExploreFinding& f : r.findings) {
    if (f.kind == "repeated-lower-m") {
      repeated = true;
      EXPECT_LT(f.orbit.periodicity_residual, 1e-10);
    }
  }
  EXPECT_TRUE(repeated);
}

TEST(Explore, FourImpactsRootsHaveKernelDimensionTwo) {
  const AnalysisBasis b = testing::PaperBasis();
  ExploreOptions opt;
  opt.impacts = 4;
  opt.grid = 10;
  const ExploreReport r = ExploreImpacts(b, {6.0}, opt);
  ASSERT_FALSE(r.findings.empty());
  for (const ExploreFinding& f : r.findings) EXPECT_EQ(f.kernel_dimension, 2);
}

TEST(Explore, RejectsImpossibleRequests) {
  ExploreOptions opt;
  opt.impacts = 2;
  EXPECT_THROW(ExploreImpacts(testing::PaperBasis(), {4.0}, opt), InputError);
}

}  // namespace
}  // namespace nsmodal

namespace nsmodal {
namespace {

TEST(Explore, AdmissibleThreeImpactOrbitThatIsNotALowerOrbit) {
  // Section 2.3 conjectures that odd-m potential solutions exist only as
  // degenerate counterparts of fewer impacts. The search finds, at T = 27.5,
  // an admissible 3-ipp orbit with impact intervals (8.359, 10.783, 8.359) and
  // three genuine impacts. Check it independently: physical state, matrix
  // exponential flow, the impact law written out, dense sampling of x2.
  const AnalysisBasis b = testing::PaperBasis();
  ExploreOptions opt;
  opt.impacts = 3;
  const ExploreReport r = ExploreImpacts(b, {27.5}, opt);
  const ExploreFinding* found = nullptr;
  for (const ExploreFinding& f : r.findings) {
    if (f.kind == "new" && f.orbit.admissible) found = &f;
  }
  ASSERT_NE(found, nullptr);
  const Model m = PaperModel();
  Eigen::VectorXd z = found->orbit.z0;
  double prev = 0.0, max_interior = -1e300, min_impact_speed = 1e300;
  std::vector<double> ends = found->orbit.times;
  ends.push_back(27.5);
  for (double t : ends) {
    const int n = 4000;
    const Eigen::MatrixXd step = testing::PhysicalFlow(m, (t - prev) / n);
    Eigen::VectorXd w = z;
    for (int k = 1; k < n; ++k) {
      w = step * w;
      max_interior = std::max(max_interior, w[1]);
    }
    z = testing::PhysicalFlow(m, t - prev) * z;
    EXPECT_NEAR(z[1], m.gap, 1e-12);  // NC2
    min_impact_speed = std::min(min_impact_speed, z[3]);
    z[3] = -z[3];  // Newton law, e = 1, diagonal M
    prev = t;
  }
  EXPECT_LT((z - found->orbit.z0).norm(), 1e-12 * found->orbit.z0.norm());  // periodic
  EXPECT_LT(max_interior, m.gap - 1e-5);                                     // NC3 with margin
  EXPECT_GT(min_impact_speed, 0.1);                                          // real impacts
}

}  // namespace
}  // namespace nsmodal
