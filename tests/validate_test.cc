#include <gtest/gtest.h>

#include <cstdio>

#include <algorithm>
#include <cmath>
#include <optional>

#include "nsmodal/bridge.h"
#include "nsmodal/error.h"
#include "nsmodal/explore.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/roots.h"
#include "nsmodal/stability.h"
#include "nsmodal/two_impact.h"
#include "nsmodal/validate.h"

namespace nsmodal {
namespace {

ValidateOptions Options(int periods) {
  ValidateOptions opt;
  opt.periods = periods;
  opt.simulate.rtol = 1e-10;
  opt.simulate.atol = 1e-12;
  return opt;
}

// Issue 14: on a 3-dof chain with the contact on the middle mass, the
// unstable 2-ipp orbit at T = 9, t2 = 7.4523 was judged inconsistent (growth
// 0.042 measured, 0.317 predicted) while its mirror t2 = 1.5477 passed: the
// deviation saturated near period 100, wandered back below 1e-2 later, and
// the fit ran over the saturated stretch. The fit stops at saturation now.
TEST(Validate, GrowthIsFittedBeforeSaturationOnly) {
  const Model m = MakeChain({1.0, 1.0, 1.0}, {1.0, 1.0, 1.0}, 1, 1.0, 1.0);
  const AnalysisBasis b(m);
  int checked = 0;
  for (const Orbit& o : TwoImpactOrbits(b, 9.0)) {
    if (!o.admissible || std::abs(o.times[0] - 4.5) < 1.0) continue;
    const OrbitValidation v = ValidateOrbit(m, o, Integrator::kExact, Options(1000));
    if (v.stability.stable || v.stability.growth_per_period > 1.0) continue;  // the pair with |lambda| = 1.37
    ++checked;
    EXPECT_TRUE(v.consistent) << "t2 = " << o.times[0] << ": " << v.reason;
    // The verdict's own tolerance is 30 %; the fit itself lands within 1 %
    // (measured 0.3168 against 0.3168 for both mirrors).
    EXPECT_NEAR(v.measured_growth, v.stability.growth_per_period, 0.01 * v.stability.growth_per_period)
        << "t2 = " << o.times[0];
  }
  EXPECT_EQ(checked, 2);  // t2 = 1.5477 and its mirror 7.4523
}

TEST(Stability, MultipliersOfAOneImpactOrbitComeInReciprocalPairsWithTrivialOnes) {
  const AnalysisBasis b(PaperModel());
  for (double period : {5.0, 6.5, 9.2, 20.0}) {
    const Stability s = OrbitStability(b, OneImpactOrbit(b, period));
    // Two trivial multipliers at 1 (a Jordan block: computed to ~sqrt(eps)).
    int ones = 0;
    for (int i = 0; i < 4; ++i) ones += std::abs(s.multipliers[i] - 1.0) < 1e-6;
    EXPECT_EQ(ones, 2) << "T = " << period;
    // The impact map is symplectic for e = 1: det M = 1, pairs (lambda, 1/lambda).
    EXPECT_NEAR(Monodromy(b, OneImpactOrbit(b, period)).determinant(), 1.0, 1e-9);
  }
  EXPECT_TRUE(OrbitStability(b, OneImpactOrbit(b, 5.0)).stable);
  EXPECT_FALSE(OrbitStability(b, OneImpactOrbit(b, 6.5)).stable);
}

// The largest |lambda - 1| over the multipliers that are not the trivial
// pair (the two closest to 1 are that pair, a Jordan block).
double NontrivialDistanceToOne(const Stability& s) {
  std::vector<double> d;
  for (int i = 0; i < s.multipliers.size(); ++i) d.push_back(std::abs(s.multipliers[i] - 1.0));
  std::sort(d.begin(), d.end());
  return d.back();
}

TEST(Stability, AMultiplierCrossesPlusOneWhereTheOneImpactEnergyIsExtremal) {
  // Along a conservative family, the nontrivial multiplier pair can only
  // leave the unit circle through +1 where the period stops being monotone
  // in the energy (dE/dT = 0). Scan T in [2, 40] away from the singular
  // periods (E < 100 at both ends of a cell), locate each zero of dE/dT by
  // Brent on a central difference, and check the crossing there.
  const AnalysisBasis b(PaperModel());
  auto energy = [&](double t) { return OneImpactOrbit(b, t).energy; };
  auto slope = [&](double t) { return (energy(t + 1e-6) - energy(t - 1e-6)) / 2e-6; };  // error ~ eps E / 1e-6
  int extrema = 0;
  for (double t = 2.0; t < 40.0; t += 0.01) {
    if (!(energy(t) < 100.0 && energy(t + 0.01) < 100.0 && slope(t) * slope(t + 0.01) < 0.0)) continue;
    const double ts = PolishRoot(slope, t, t + 0.01);
    ++extrema;
    const Stability left = OrbitStability(b, OneImpactOrbit(b, ts - 1e-3));
    const Stability right = OrbitStability(b, OneImpactOrbit(b, ts + 1e-3));
    EXPECT_NE(left.stable, right.stable) << "T* = " << ts;
    const Stability& unstable = left.stable ? right : left;
    // The escaping multiplier is real and > 1 (a +1 crossing, not a flip at -1).
    EXPECT_GT(unstable.multipliers[0].real(), 1.0) << "T* = " << ts;
    EXPECT_LT(std::abs(unstable.multipliers[0].imag()), 1e-9) << "T* = " << ts;
    // At a fold |lambda - 1| ~ sqrt|T - T*|: a thousand times closer, about
    // 30 times nearer to 1 (at least 10 asked: the slope's own error moves
    // T* by ~1e-9).
    const double far = std::max(NontrivialDistanceToOne(left), NontrivialDistanceToOne(right));
    const double near = std::max(NontrivialDistanceToOne(OrbitStability(b, OneImpactOrbit(b, ts - 1e-6))),
                                 NontrivialDistanceToOne(OrbitStability(b, OneImpactOrbit(b, ts + 1e-6))));
    EXPECT_LT(near, 0.1 * far) << "T* = " << ts;
  }
  EXPECT_GE(extrema, 10);  // 16 on [2, 40]; far fewer means the scan broke
}

TEST(Validate, StableAdmissibleOrbitIsPeriodicOverAThousandPeriods) {
  const Model m = PaperModel();
  const AnalysisBasis b(m);
  const OrbitValidation v = ValidateOrbit(m, OneImpactOrbit(b, 7.5), Integrator::kExact, Options(1000));
  EXPECT_TRUE(v.stability.stable);
  EXPECT_TRUE(v.consistent) << v.reason;
  EXPECT_EQ(v.deviation.size(), 1000u);
  EXPECT_LT(v.deviation.back(), 1e-11);
  EXPECT_EQ(v.first_period_impacts, 1);
  EXPECT_EQ(v.impacts, 1000);
  // Post-impact states stay on the family, also from a neighbouring orbit.
  EXPECT_LT(v.manifold_distance, 1e-12);
  EXPECT_LT(v.perturbed_manifold_distance, 1e-12);
}

// The admissible 3-ipp family of the paper's system (explore.h) is unstable
// except in a window T ~ 28.8449 to 28.8651 (found stepping by 1e-4), where
// its multipliers lie on the unit circle. Simulation agrees: inside, the
// orbit stays within 2.8e-9 over 1,000 periods (3,000 impacts); outside
// (T = 28.80), it leaves within tens of periods.
TEST(Validate, TheThreeImpactFamilyHasAStableWindowThatSimulationConfirms) {
  const Model m = PaperModel();
  const AnalysisBasis b(m);
  ExploreOptions opt;
  opt.impacts = 3;
  std::optional<Orbit> start;
  for (const ExploreFinding& f : ExploreImpacts(b, {27.5}, opt).findings) {
    if (f.kind == "new" && f.orbit.admissible) start = f.orbit;
  }
  ASSERT_TRUE(start.has_value());
  const Orbit inside = FollowOddImpactFamily(b, *start, 28.855).orbits.back();
  const Orbit outside = FollowOddImpactFamily(b, *start, 28.80).orbits.back();
  ASSERT_TRUE(inside.admissible && outside.admissible);
  const OrbitValidation in = ValidateOrbit(m, inside, Integrator::kExact, Options(1000));
  EXPECT_TRUE(in.stability.stable);
  // (The batch verdict calls it "drifted": its fixed 1e-9 for stable orbits
  // was set on 1-ipp orbits; here 3,000 impacts leave 3.8e-9. The bound
  // below is this orbit's, and the contrast with the unstable neighbour is
  // the confirmation.)
  EXPECT_EQ(in.impacts, 3000);
  // On the circle nothing decays: round-off (1e-16 a step) accumulates at
  // most linearly over 3,000 impacts with the orbit's sensitivity; 1e-7 is
  // 35 times the measured 2.8e-9.
  EXPECT_LT(in.deviation.back(), 1e-7);
  const OrbitValidation out = ValidateOrbit(m, outside, Integrator::kExact, Options(200));
  EXPECT_FALSE(out.stability.stable);
  EXPECT_TRUE(out.consistent) << out.reason;
  EXPECT_GT(*std::max_element(out.deviation.begin(), out.deviation.end()), 1e-2);
}

TEST(Validate, UnstableOrbitDeviatesAtTheRateOfItsMultipliers) {
  const Model m = PaperModel();
  const AnalysisBasis b(m);
  for (Integrator integrator : {Integrator::kExact, Integrator::kCvode}) {
    const OrbitValidation v = ValidateOrbit(m, OneImpactOrbit(b, 6.5), integrator, Options(200));
    EXPECT_FALSE(v.stability.stable);
    EXPECT_TRUE(v.consistent) << v.reason;
    // The rate is fitted over a decade or more of growth: 10 % agreement
    // (measured: 0.02 % exact, 0.06 % cvode).
    EXPECT_NEAR(v.measured_growth, v.stability.growth_per_period, 0.1 * v.stability.growth_per_period)
        << ToString(integrator);
  }
}

TEST(Validate, AnOffFamilyPerturbationStaysSmallOnStableOrbitsAndGrowsAtTheMultipliersRateOnUnstableOnes) {
  // Issue 5: perturb each admissible 1- and 2-ipp orbit of a period grid by
  // 1e-6 |y| in its nontrivial Floquet subspace and run 1000 periods with the
  // exact integrator.
  const Model m = PaperModel();
  const AnalysisBasis b(m);
  int stable = 0, unstable = 0;
  double worst_stable = 0.0, worst_rate = 0.0;
  for (double period = 4.0; period <= 30.0; period += 1.0) {
    std::vector<Orbit> orbits = TwoImpactOrbits(b, period);
    orbits.push_back(OneImpactOrbit(b, period));
    for (const Orbit& o : orbits) {
      if (!o.admissible) continue;
      const OrbitValidation v = ValidateOrbit(m, o, Integrator::kExact, Options(1000));
      if (v.stability.stable) {
        // Elliptic multipliers rotate the perturbation without growth; its
        // size changes only by the condition of the eigenvector basis
        // (measured at most 1.8 here). 100 fails on any growth of 0.5 % per
        // period or more (1.005^1000 = 147).
        EXPECT_EQ(v.perturbed_periods, 1000) << "T = " << period;
        EXPECT_LT(v.perturbed_amplification, 100.0) << "T = " << period;
        worst_stable = std::max(worst_stable, v.perturbed_amplification);
        ++stable;
      } else {
        // Fitted over three decades (1e-5 to 1e-2 relative) once per period:
        // 5 % of the rate. A rate below 0.01 gives fewer than four decades in
        // 1000 periods; above 1.5, fewer than the fit's four points.
        const double rate = v.stability.growth_per_period;
        if (rate < 0.01 || rate > 1.5) continue;
        EXPECT_NEAR(v.perturbed_growth, rate, 0.05 * rate) << "T = " << period;
        worst_rate = std::max(worst_rate, std::abs(v.perturbed_growth / rate - 1.0));
        ++unstable;
      }
    }
  }
  EXPECT_GE(stable, 5);
  EXPECT_GE(unstable, 5);
  std::printf("worst amplification of a stable orbit %.3g, worst relative rate error %.2g; %d stable, %d unstable\n",
              worst_stable, worst_rate, stable, unstable);
}

TEST(Validate, SimulationConfirmsTheStabilityOfTheBridgeOrbits) {
  // The bridge at T_G = 19.242 (bridge.h): 2-ipp orbits of one period,
  // unstable except the middle (bridge_test). Simulated with the exact
  // integrator, each keeps its two impacts at the predicted times in the
  // first period; the unstable ones depart at log|lambda| per period, the
  // middle one stays periodic for 1000 periods.
  const Model m = PaperModel();
  const AnalysisBasis b(m);
  const Bridge br = BridgeAt(b, 19.242270772853061);
  for (double f : {0.1, 0.3, 0.5, 0.7, 0.9}) {
    const Orbit o = BridgeOrbit(b, br, f * br.s_end);
    ASSERT_TRUE(o.admissible) << o.reason;
    const OrbitValidation v = ValidateOrbit(m, o, Integrator::kExact, Options(1000));
    EXPECT_TRUE(v.consistent) << "s = " << f << " s_end: " << v.reason;
    EXPECT_EQ(v.first_period_impacts, 2);
    if (f == 0.5) {
      EXPECT_EQ(v.impacts, 2000);
      EXPECT_LT(v.deviation.back(), 1e-9);  // options.exact_periodicity
    } else {
      // Same 5 % as the perturbation test above (three decades, once per period).
      EXPECT_NEAR(v.perturbed_growth, v.stability.growth_per_period, 0.05 * v.stability.growth_per_period)
          << "s = " << f << " s_end";
    }
  }
}

TEST(Validate, PotentialButNotAdmissibleOrbitsBreak) {
  const Model m = PaperModel();
  const AnalysisBasis b(m);
  int checked = 0;
  for (const Orbit& o : TwoImpactOrbits(b, 9.0)) {
    if (o.admissible || !o.potential) continue;
    const OrbitValidation v = ValidateOrbit(m, o, Integrator::kExact, Options(10));
    EXPECT_TRUE(v.consistent) << v.reason;
    EXPECT_TRUE(v.first_period_impacts != 2 || v.impact_time_error.value() > 1e-9) << "t2 = " << o.times[0];
    ++checked;
  }
  EXPECT_GE(checked, 3);
}

TEST(Validate, BatchOverTheDefaultSceneIsConsistentWithTheExactIntegrator) {
  const Model m = PaperModel();
  const AnalysisBasis b(m);
  std::vector<Orbit> orbits;
  for (double period = 2.0; period <= 12.0; period += 0.5) {
    orbits.push_back(OneImpactOrbit(b, period));
    for (const Orbit& o : TwoImpactOrbits(b, period)) orbits.push_back(o);
  }
  const std::vector<OrbitValidation> res = ValidateOrbits(m, orbits, Options(200));
  ASSERT_EQ(res.size(), orbits.size());
  int admissible = 0;
  for (const OrbitValidation& v : res) {
    EXPECT_TRUE(v.consistent) << "T = " << v.orbit.period << ": " << v.reason;
    admissible += v.orbit.admissible;
  }
  EXPECT_GT(admissible, 10);
}

TEST(Validate, OptionsAreChecked) {
  ValidateOptions opt;
  opt.periods = 0;
  EXPECT_THROW(opt.Validate(), InputError);
  opt = ValidateOptions();
  opt.integrators.clear();
  EXPECT_THROW(opt.Validate(), InputError);
}

// The simulations' work is estimated before they start (validate.h): the
// paper's validation at 1,000 periods is accepted, at 1e8 refused naming the
// field; the estimate grows linearly in the simulated time and in the
// integrators asked.
TEST(Validate, SimulationWorkIsBoundedBeforeItStarts) {
  const Model m = PaperModel();
  ValidateOptions opt = Options(1000);
  opt.integrators = {Integrator::kExact, Integrator::kCvode};
  const double one = ValidationSeconds(m, 1e6, opt);
  EXPECT_GT(one, 0.0);
  EXPECT_NEAR(ValidationSeconds(m, 2e6, opt), 2.0 * one, 1e-12 * one);
  opt.integrators.push_back(Integrator::kMoreauJean);
  EXPECT_GT(ValidationSeconds(m, 1e6, opt), one);
  EXPECT_NO_THROW(CheckValidationWork(m, 1e6, 62, opt));
  try {
    CheckValidationWork(m, 1e11, 420, opt, FieldNames().Set("periods", "--periods"));
    ADD_FAILURE() << "1e11 time units with three integrators accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--periods");
  }
}

}  // namespace
}  // namespace nsmodal

namespace nsmodal {
namespace {

// The paper's chain between two stops, x2 <= 1 and x2 >= -1.2 (configs/clearance.toml).
Model Clearance() {
  Model m = PaperModel();
  m.contacts.push_back(DofContact(2, 1, false, 1.2, 1.0));
  Validate(m);
  return m;
}

// explore with a sequence (issue 24): on one contact it is the one-contact
// search (the same findings, to round-off); across two walls its new
// admissible orbits are potential (NC2 on each impact's own wall, periodic)
// and the exact simulator follows them: each impact at its predicted time
// on its predicted wall (validate's verdict), over 20 periods.
TEST(Explore, ASequenceOverTwoWallsFindsOrbitsTheSimulatorConfirms) {
  const Model m = Clearance();
  const AnalysisBasis b(m);
  ExploreOptions one;
  one.impacts = 3;
  ExploreOptions same = one;
  same.sequence = {0, 0, 0};
  const ExploreReport a = ExploreImpacts(b, {27.0, 28.0}, one), c = ExploreImpacts(b, {27.0, 28.0}, same);
  ASSERT_EQ(a.findings.size(), c.findings.size());
  for (std::size_t i = 0; i < a.findings.size(); ++i) {
    EXPECT_EQ(a.findings[i].kind, c.findings[i].kind);
    for (std::size_t k = 0; k < a.findings[i].orbit.times.size(); ++k) {
      EXPECT_NEAR(a.findings[i].orbit.times[k], c.findings[i].orbit.times[k], 1e-12 * 28.0);
    }
  }
  ExploreOptions two = one;
  two.sequence = {0, 0, 1};
  int checked = 0;
  for (const ExploreFinding& f : ExploreImpacts(b, {3.5, 4.0, 4.5, 5.0}, two).findings) {
    EXPECT_EQ(f.orbit.sequence, two.sequence);
    EXPECT_LT(f.orbit.nc2_residual, 1e-9);
    EXPECT_LT(f.orbit.periodicity_residual, 1e-9);
    if (f.kind != "new" || !f.orbit.admissible) continue;
    const OrbitValidation v = ValidateOrbit(m, f.orbit, Integrator::kExact, Options(20));
    EXPECT_TRUE(v.consistent) << "T = " << f.orbit.period << ": " << v.reason;
    ASSERT_TRUE(v.impact_time_error.has_value()) << v.reason;  // the predicted impacts on the predicted walls
    EXPECT_LT(*v.impact_time_error, 1e-9);
    ++checked;
  }
  EXPECT_GE(checked, 3);
  two.sequence = {0, 2, 1};
  EXPECT_THROW(ExploreImpacts(b, {4.0}, two), InputError);
}

}  // namespace
}  // namespace nsmodal
