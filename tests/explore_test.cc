#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "fixtures.h"
#include "nsmodal/error.h"
#include "nsmodal/explore.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/stability.h"
#include "nsmodal/transitions.h"

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

// The admissible 3-ipp orbit that is not a lower-m orbit, found by the
// search at T (the last such finding), if any.
std::optional<ExploreFinding> AdmissibleNewThreeImpactOrbit(const AnalysisBasis& b, double period) {
  ExploreOptions opt;
  opt.impacts = 3;
  std::optional<ExploreFinding> found;
  for (const ExploreFinding& f : ExploreImpacts(b, {period}, opt).findings) {
    if (f.kind == "new" && f.orbit.admissible) found = f;
  }
  return found;
}

TEST(Explore, AdmissibleThreeImpactOrbitThatIsNotALowerOrbit) {
  // Section 2.3 conjectures that odd-m potential solutions exist only as
  // degenerate counterparts of fewer impacts. The search finds, at T = 27.5,
  // an admissible 3-ipp orbit with impact intervals (8.359, 10.783, 8.359) and
  // three genuine impacts. Check it independently: physical state, matrix
  // exponential flow, the impact law written out, dense sampling of x2.
  const AnalysisBasis b = testing::PaperBasis();
  const std::optional<ExploreFinding> found = AdmissibleNewThreeImpactOrbit(b, 27.5);
  ASSERT_TRUE(found.has_value());
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
    EXPECT_NEAR(z[1], m.FirstContact().gap, 1e-12);  // NC2
    min_impact_speed = std::min(min_impact_speed, z[3]);
    z[3] = -z[3];  // Newton law, e = 1, diagonal M
    prev = t;
  }
  EXPECT_LT((z - found->orbit.z0).norm(), 1e-12 * found->orbit.z0.norm());  // periodic
  EXPECT_LT(max_interior, m.FirstContact().gap - 1e-5);                                     // NC3 with margin
  EXPECT_GT(min_impact_speed, 0.1);                                          // real impacts
}

}  // namespace
}  // namespace nsmodal

namespace nsmodal {
namespace {

// The admissible 3-impact family of the paper's system, followed in T from
// the orbit the search finds at T = 27.5 (issue 13: the README's 26.8-28.3
// came from a coarse grid). Upwards it stays admissible until the grazing
// transition of the 1-ipp family, T_G = 29.3072, where one of its impacts
// becomes a grazing contact of the 1-ipp orbit; downwards until T = 26.5714.
// Every point is a potential orbit (NC2 to 1e-12 of d), and it is unstable.
TEST(Explore, TheAdmissibleThreeImpactFamilyIsFollowedToItsEnds) {
  const AnalysisBasis b = testing::PaperBasis();
  const std::optional<ExploreFinding> found = AdmissibleNewThreeImpactOrbit(b, 27.5);
  ASSERT_TRUE(found.has_value());
  const Orbit* start = &found->orbit;
  const Family up = FollowOddImpactFamily(b, *start, 30.0);
  const Family down = FollowOddImpactFamily(b, *start, 26.0);
  // The grazing transition, computed independently from the 1-ipp family.
  double t_g = 0.0, e_g = 0.0;
  for (const Transition& t : OneImpactTransitions(b, 29.0, 29.5, 0.01)) {
    if (t.kind == TransitionKind::kGrazing) {
      t_g = t.period;
      e_g = t.energy;
    }
  }
  ASSERT_GT(t_g, 0.0);
  // Located by bisection to 1e-12 T; at a grazing contact the NC1 velocity
  // margin vanishes like sqrt(T_G - T), so the admissibility change and T_G
  // agree to the square of the NC1 tolerance's reach: 1e-8 is what is asserted.
  EXPECT_NEAR(up.admissibility_change, t_g, 1e-8) << up.stop;
  EXPECT_NEAR(down.admissibility_change, 26.5714, 1e-4) << down.stop;
  // It ends on the grazing 1-ipp orbit: the same energy there (measured
  // 0.411044350 both; the 3-ipp orbit is within ~1e-12 in T of T_G).
  EXPECT_NEAR(up.at_change.energy, e_g, 1e-8);
  for (const Family* fam : {&up, &down}) {
    ASSERT_GE(fam->orbits.size(), 50u) << fam->stop;
    for (const Orbit& o : fam->orbits) {
      if (o.potential) {
        EXPECT_LT(o.nc2_residual, 1e-11) << "T = " << o.period;
      }
    }
  }
  // Unstable along the admissible stretch (a multiplier outside the circle).
  for (double f : {0.1, 0.5, 0.9}) {
    const double target = down.admissibility_change + f * (up.admissibility_change - down.admissibility_change);
    const Orbit* nearest = &up.orbits.front();
    for (const Family* fam : {&up, &down}) {
      for (const Orbit& o : fam->orbits) {
        if (std::abs(o.period - target) < std::abs(nearest->period - target)) nearest = &o;
      }
    }
    ASSERT_TRUE(nearest->admissible) << nearest->period;
    const Stability s = OrbitStability(b, *nearest);
    EXPECT_TRUE(s.defined);
    EXPECT_GT(s.max_modulus, 1.0 + 1e-3) << "T = " << nearest->period;
  }
}

// Past T_G the family (no longer admissible) passes an energy peak above
// 1e5 J near T = 29.761. Written with its impact times reversed (t2, t3) ->
// (t3 - t2, t3), the same orbits, as the figures' search finds it, Newton
// converged there on another branch before the landing check (t2 jumping
// from 11.98 to 14.17, 2.2 s, between T = 29.75 and 29.76) and the family
// went on as if it were the same. Now every step stays on the branch: the
// impact times move by at most 0.2 s between points (the largest step the
// family makes in either writing measured 0.067 s, near its fold at
// T = 29.943), and where it can go no further it says why: the first
// writing stops at the fold, the reversed one just before the peak (29.7595
// from this start: Newton does not reach 1e-13 there), both past 29.75.
TEST(Explore, TheFamilyContinuationDoesNotJumpToAnotherBranch) {
  const AnalysisBasis b = testing::PaperBasis();
  const std::optional<ExploreFinding> found = AdmissibleNewThreeImpactOrbit(b, 27.5);
  ASSERT_TRUE(found.has_value());
  Orbit reversed = found->orbit;
  reversed.times = {found->orbit.times[1] - found->orbit.times[0], found->orbit.times[1]};
  for (const Orbit& start : {found->orbit, reversed}) {
    const Family up = FollowOddImpactFamily(b, start, 30.0);
    EXPECT_GT(up.orbits.back().period, 29.75) << up.stop;
    EXPECT_LT(up.orbits.back().period, 29.95) << up.stop;
    EXPECT_NE(up.stop.find("beyond T = "), std::string::npos) << up.stop;
    for (std::size_t k = 2; k < up.orbits.size(); ++k) {
      for (std::size_t i = 0; i < up.orbits[k].times.size(); ++i) {
        EXPECT_LT(std::abs(up.orbits[k].times[i] - up.orbits[k - 1].times[i]), 0.2) << "T = " << up.orbits[k].period;
      }
    }
  }
}

TEST(Explore, FamilyRequestsAreChecked) {
  const AnalysisBasis b = testing::PaperBasis();
  const Orbit one = OneImpactOrbit(b, 5.0);
  EXPECT_THROW(FollowOddImpactFamily(b, one, 6.0), InputError);
}

}  // namespace
}  // namespace nsmodal

namespace nsmodal {
namespace {

// Two impacts at one instant: on one contact they cancel (a lower-m orbit),
// on two contacts they are a simultaneous impact (issue 24's review).
TEST(Explore, CoincidentImpactsAreToldApartByTheirContacts) {
  const double period = 10.0;
  // Impacts at 0, 4, 4 + 1e-8 (coincident to 1e-6 T) with contacts (1, 1, 2).
  const std::vector<double> times{4.0, 4.0 + 1e-8};
  EXPECT_TRUE(CoincidentImpacts(times, period, 3, {0, 0, 1}, false));
  EXPECT_FALSE(CoincidentImpacts(times, period, 3, {0, 0, 1}, true));
  EXPECT_TRUE(CoincidentImpacts(times, period, 3, {0, 1, 1}, true));
  // The last impact and the next period's first (at T): (2, 1, 1) wraps.
  EXPECT_TRUE(CoincidentImpacts({4.0, period - 1e-8}, period, 3, {0, 1, 0}, true));
  EXPECT_TRUE(CoincidentImpacts({4.0, period - 1e-8}, period, 3, {1, 0, 0}, false));
  // An empty sequence is every impact on contact 1.
  EXPECT_TRUE(CoincidentImpacts(times, period, 3, {}, true));
  EXPECT_FALSE(CoincidentImpacts(times, period, 3, {}, false));
  // Apart by more than 1e-6 T: neither.
  EXPECT_FALSE(CoincidentImpacts({4.0, 4.001}, period, 3, {0, 0, 1}, false));
  EXPECT_FALSE(CoincidentImpacts({4.0, 4.001}, period, 3, {0, 1, 1}, true));
}

}  // namespace
}  // namespace nsmodal
