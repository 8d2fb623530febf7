// The witness rule (witness.h) on its edge cases, on the rule itself and on
// the integrators that implement it: a witness exactly zero at a step's start
// does not fire, a sign change inside a step does, and a tangency is handed
// to the graze logic. The scene: one mass m = 1 on a spring k = 1 with a wall
// at d = 1, so x(t) = x0 cos t + v0 sin t in flight.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "nsmodal/simulate.h"
#include "nsmodal/witness.h"

namespace nsmodal {
namespace {

TEST(Witness, TheRuleOnAStepsEnds) {
  constexpr auto kDown = WitnessDirection::kPositiveThenNonPositive;
  EXPECT_TRUE(Fires(kDown, 1.0, -1.0));   // a sign change
  EXPECT_TRUE(Fires(kDown, 1.0, 0.0));    // reaching zero at the step's end: (t0, t1] is closed there
  EXPECT_FALSE(Fires(kDown, 0.0, -1.0));  // zero at the start (the gap just after an impact)
  EXPECT_FALSE(Fires(kDown, 0.0, 0.0));
  EXPECT_FALSE(Fires(kDown, -1.0, -2.0));  // already past: no new crossing
  EXPECT_FALSE(Fires(kDown, 1.0, 0.5));    // a dip that came back up (a tangency) is not a crossing
  EXPECT_EQ(ContactWitness(0, false).name, "contact 1 gap");
  EXPECT_EQ(ContactWitness(1, true).name, "contact 2 force");
  EXPECT_EQ(ContactWitness(1, true).kind, WitnessKind::kContactForce);
}

Model OneMass() { return MakeChain({1.0}, {1.0}, 0, 1.0, 1.0); }

struct OneMassRun {
  SimulationSummary summary;
  std::vector<double> impacts;
};

OneMassRun Simulate1(Integrator integrator, double x0, double v0, double t_end) {
  SimulateOptions opt;
  opt.integrator = integrator;
  opt.t_end = t_end;
  opt.sample_dt = 0.0;
  opt.step = 1e-5;
  OneMassRun r;
  SimulationObserver obs;
  obs.on_impact = [&](const ContactEvent& ev) { r.impacts.push_back(ev.t); };
  r.summary = Simulate(OneMass(), Eigen::VectorXd::Constant(1, x0), Eigen::VectorXd::Constant(1, v0), opt, obs);
  EXPECT_EQ(r.summary.status, SimulationStatus::kFinished) << r.summary.message;
  return r;
}

// The impact time's tolerance per integrator: the exact one locates the
// crossing to root_tol (1e-14) relative, so 1e-12 leaves room for the
// flight's round-off over t ~ 5; CVODE at rtol 1e-10 locates roots to its
// local error, ~1e-9 here, so 1e-7; Moreau-Jean reports the end of the
// step in which the impulse acts, so one step (1e-5) and its first-order
// error.
double TimeTolerance(Integrator integrator) {
  switch (integrator) {
    case Integrator::kExact: return 1e-12;
    case Integrator::kCvode: return 1e-7;
    case Integrator::kMoreauJean: return 2e-5;
  }
  return 0.0;
}

class WitnessInIntegrators : public ::testing::TestWithParam<Integrator> {};

// Started on the wall moving away (the state just after an impact: the gap's
// witness is exactly zero): no impact at the start; the one sign change
// inside the flight fires, at cos t - 0.5 sin t = 1 rising, t = 2 pi - 2 atan(1/2).
TEST_P(WitnessInIntegrators, ZeroAtTheStartDoesNotFireAndASignChangeDoes) {
  const OneMassRun r = Simulate1(GetParam(), 1.0, -0.5, 6.0);
  ASSERT_EQ(r.impacts.size(), 1u);
  EXPECT_NEAR(r.impacts[0], 2.0 * M_PI - 2.0 * std::atan(0.5), TimeTolerance(GetParam()));
  EXPECT_EQ(r.summary.grazes, 0);
}

// x = -cos t touches the wall at t = pi with v = 0 and the spring pulling it
// back (a tangency, no sign change): a graze, no impulse, counted once.
// (Moreau-Jean captures contacts in its LCP and has no graze logic.)
TEST(Witness, ATangencyIsAGrazeInTheEventDrivenIntegrators) {
  for (Integrator integrator : {Integrator::kExact, Integrator::kCvode}) {
    SCOPED_TRACE(ToString(integrator));
    const OneMassRun r = Simulate1(integrator, -1.0, 0.0, 4.0);
    EXPECT_TRUE(r.impacts.empty());
    EXPECT_EQ(r.summary.grazes, 1);
    // No impulse: the motion goes on as the free flight's (1e-6: CVODE's
    // global error at rtol 1e-10 over 4 time units is far below it).
    EXPECT_NEAR(r.summary.final_state[0], -std::cos(4.0), 1e-6);
  }
}

INSTANTIATE_TEST_SUITE_P(All, WitnessInIntegrators,
                         ::testing::Values(Integrator::kExact, Integrator::kCvode, Integrator::kMoreauJean),
                         [](const ::testing::TestParamInfo<Integrator>& info) {
                           std::string name = ToString(info.param);
                           return name == "moreau-jean" ? std::string("MoreauJean") : name;
                         });

}  // namespace
}  // namespace nsmodal
