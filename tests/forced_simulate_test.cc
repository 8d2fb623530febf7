// Simulation with damping and forcing (issue 11), against closed forms and
// an independent event-driven evaluation.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "forced_fixtures.h"
#include "nsmodal/error.h"
#include "nsmodal/modal_basis.h"
#include "nsmodal/simulate.h"

namespace nsmodal {
namespace {

using testing::DampedForcedPaper;
using testing::ReceptanceState;
using testing::TextbookSimulator;

SimulationSummary Sim(const Model& m, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0, double t_end,
                      Integrator integrator = Integrator::kExact, double step = 1e-3) {
  SimulateOptions opt;
  opt.integrator = integrator;
  opt.t_end = t_end;
  opt.sample_dt = 0.0;
  opt.step = step;
  return Simulate(m, x0, v0, opt);
}

TEST(ForcedSimulation, LinearLimitIsTheReceptanceResponse) {
  // The obstacle far away (never reached); Rayleigh damping strong enough
  // that the transient has decayed by e^-59 at t = 1000.
  Model m = DampedForcedPaper();
  m.FirstContact().gap = 1e3;
  m.damping = RayleighDamping(m.mass, m.stiffness, 0.1, 0.05);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(2);
  const double t_end = 1000.0;
  const Eigen::VectorXd expected = ReceptanceState(m, t_end);
  const SimulationSummary exact = Sim(m, zero, zero, t_end);
  ASSERT_EQ(exact.status, SimulationStatus::kFinished) << exact.message;
  EXPECT_EQ(exact.impacts, 0);
  // Round-off: the forcing's phase w t at t = 1000 carries ~1e-13 rad.
  EXPECT_LT((exact.final_state - expected).norm(), 1e-12 * expected.norm());
  // CVODE at its default rtol 1e-10 on a contracting flow: its local errors
  // are damped, the end within ~10 rtol.
  const SimulationSummary cvode = Sim(m, zero, zero, t_end, Integrator::kCvode);
  EXPECT_LT((cvode.final_state - expected).norm(), 1e-9 * expected.norm());
  // Moreau-Jean (theta = 1/2, the trapezoidal rule in flight) is second order
  // in flight: its phase error at h = 1e-3, w = 0.7 is ~h^2 w^3 / 12 per unit
  // time, settled by the damping at ~1e-7 relative.
  const SimulationSummary mj = Sim(m, zero, zero, t_end, Integrator::kMoreauJean);
  EXPECT_LT((mj.final_state - expected).norm(), 1e-6 * expected.norm());
}

TEST(ForcedSimulation, ExactMatchesAnIndependentEvaluationOver1000ForcingPeriods) {
  // The response settles on a stable orbit with one impact per forcing
  // period, so round-off does not grow. (With C = 0.01 M + 0.02 K and w = 0.7
  // the response has ~1.3 impacts per period, irregular: there the two
  // evaluations part by 3.5e-10 after 1,000 periods, growing with time as
  // round-off does along a non-periodic motion.)
  const Model m = DampedForcedPaper();
  const double t_end = 1000.0 * 2.0 * M_PI / m.forcing.frequency;
  const Eigen::VectorXd x0 = Eigen::Vector2d(0.2, -0.1), v0 = Eigen::Vector2d(0.0, 0.3);
  long impacts = 0;
  const Eigen::VectorXd expected = TextbookSimulator(m).Run(x0, v0, t_end, &impacts);
  const SimulationSummary s = Sim(m, x0, v0, t_end);
  ASSERT_EQ(s.status, SimulationStatus::kFinished) << s.message;
  ASSERT_GT(impacts, 990);  // one impact a period once settled
  EXPECT_EQ(s.impacts, impacts);
  EXPECT_EQ(s.grazes, 0);
  // The target: 1e-10 after 1,000 forcing periods.
  EXPECT_LT((s.final_state - expected).norm(), 1e-10) << s.final_state.transpose() << "\n" << expected.transpose();
}

TEST(ForcedSimulation, IntegratorsAgreeWithDampingAndForcing) {
  const Model m = DampedForcedPaper();
  const Eigen::VectorXd x0 = Eigen::Vector2d(0.2, -0.1), v0 = Eigen::Vector2d(0.0, 0.3);
  const SimulationSummary exact = Sim(m, x0, v0, 200.0);
  const SimulationSummary cvode = Sim(m, x0, v0, 200.0, Integrator::kCvode);
  ASSERT_EQ(cvode.status, SimulationStatus::kFinished) << cvode.message;
  EXPECT_EQ(cvode.impacts, exact.impacts);
  // CVODE's local errors (rtol 1e-10 of a state of order 1) carried through
  // 15 impacts of a damped, contracting motion: 100 rtol (4.4e-10 measured).
  EXPECT_LT((cvode.final_state - exact.final_state).norm(), 1e-8);
  // Moreau-Jean is first order at impacts: halving h halves its error
  // (1.06e-3 -> 6.2e-4 measured).
  const double e1 = (Sim(m, x0, v0, 200.0, Integrator::kMoreauJean, 2e-3).final_state - exact.final_state).norm();
  const double e2 = (Sim(m, x0, v0, 200.0, Integrator::kMoreauJean, 1e-3).final_state - exact.final_state).norm();
  EXPECT_LT(e2, 0.7 * e1) << e1 << " " << e2;
  EXPECT_LT(e2, 2e-3);
}

TEST(ForcedSimulation, ARunStartedAtTStartSeesTheForcingAtItsPhase) {
  // The run from 0 to 200 and the same motion restarted at t1 = 83.7 from its
  // state there reach the same end (impacts before and after t1): the
  // restart's forcing starts at w t1. Each integrator to its own error:
  // exact, round-off (1e-16 measured, 1e-11 allowed); cvode, rtol 1e-10
  // through the impacts and the restart (1e-8 allowed, as above); Moreau-Jean
  // with t1 on its step grid takes the same steps (round-off of t1 + k h).
  // Restarted at 0 instead, the forcing is shifted by w t1: order 1 apart.
  const Model m = DampedForcedPaper();
  const Eigen::VectorXd x0 = Eigen::Vector2d(0.2, -0.1), v0 = Eigen::Vector2d(0.0, 0.3);
  const double t1 = 83.7;
  for (Integrator integrator : {Integrator::kExact, Integrator::kCvode, Integrator::kMoreauJean}) {
    SCOPED_TRACE(ToString(integrator));
    const SimulationSummary first = Sim(m, x0, v0, t1, integrator);
    const SimulationSummary whole = Sim(m, x0, v0, 200.0, integrator);
    ASSERT_GT(first.impacts, 0);
    ASSERT_GT(whole.impacts, first.impacts);
    SimulateOptions opt;
    opt.integrator = integrator;
    opt.t_start = t1;
    opt.t_end = 200.0;
    opt.sample_dt = 10.0;
    std::vector<double> samples;
    SimulationObserver obs;
    obs.on_sample = [&samples](double t, const Eigen::VectorXd&) { samples.push_back(t); };
    const Eigen::Index n = x0.size();
    const SimulationSummary rest = Simulate(m, first.final_state.head(n), first.final_state.tail(n), opt, obs);
    EXPECT_EQ(rest.final_time, 200.0);
    EXPECT_EQ(first.impacts + rest.impacts, whole.impacts);
    const double tol = integrator == Integrator::kCvode ? 1e-8 : 1e-11;
    EXPECT_LT((rest.final_state - whole.final_state).norm(), tol);
    opt.t_start = 0.0;
    opt.t_end = 200.0 - t1;
    const SimulationSummary shifted = Simulate(m, first.final_state.head(n), first.final_state.tail(n), opt);
    EXPECT_GT((shifted.final_state - whole.final_state).norm(), 1e-2);
    // The sample grid counts from t_start.
    ASSERT_EQ(samples.size(), 12u);
    EXPECT_EQ(samples.front(), t1);
    EXPECT_DOUBLE_EQ(samples.back(), t1 + 110.0);
  }
  SimulateOptions bad;
  bad.t_end = 10.0;
  bad.t_start = 10.0;
  try {
    bad.Validate();
    ADD_FAILURE() << "t_start = t_end accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "simulate.t_start");
    EXPECT_NE(std::string(e.what()).find("must be in [0, t_end = 10), got 10"), std::string::npos) << e.what();
  }
}

// A unit oscillator preloaded by f0 = 2 towards a wall at d = 1: its
// equilibrium x = 2 lies beyond the wall. From rest at 0 it reaches the wall
// at t1 = acos(1 - d / f0) = pi / 3 with v1 = f0 sin t1 = sqrt(3); each flight
// from the wall with speed u returns after 2 atan(u / (f0 - d)) (x - f0
// rotates at unit rate), so with e = 1/2 the impacts accumulate at
//   t_inf = t1 + sum_{k >= 1} 2 atan(e^k v1 / (f0 - d)),
// after which the contact force f0 - d > 0 holds the mass for good.
TEST(ForcedSimulation, PreloadBeyondTheWallEndsInZenoThenSticksForGood) {
  Model m = MakeChain({1.0}, {1.0}, 0, 1.0, 0.5);
  m.forcing.constant = Eigen::VectorXd::Constant(1, 2.0);
  double t_inf = M_PI / 3.0;
  for (int k = 1; k < 200; ++k) t_inf += 2.0 * std::atan(std::pow(0.5, k) * std::sqrt(3.0) / 1.0);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(1);
  const SimulationSummary s = Sim(m, zero, zero, 20.0);
  ASSERT_EQ(s.status, SimulationStatus::kFinished) << s.message;
  EXPECT_EQ(s.zeno_events, 1);
  EXPECT_EQ(s.sticking_phases, 1);
  // The time of a slow impact is ill-conditioned: a round-off of the gap
  // (~2 ulps of the static response x = 2, 4e-16) moves it by 4e-16 / v, and
  // the last resolved impacts come at v ~ sqrt(2 a tol) ~ 2e-7 (the band
  // tol ~ 1e-14): ~2e-9 for each of the slowest. The summed tail's constant-
  // acceleration arcs differ from the true ones by O(v^3): nothing.
  // (Before the fix of first_rise.h's unarmed step it was 2.7e-7 off.)
  EXPECT_NEAR(s.first_zeno_time, t_inf, 1e-9);
  EXPECT_NEAR(s.sticking_time, 20.0 - t_inf, 1e-9);
  EXPECT_EQ(s.final_state[0], 1.0);
  EXPECT_EQ(s.final_state[1], 0.0);
  // CVODE resolves the same accumulation within its contact band xtol ~ 1e-9
  // (10 (atol + rtol d)): its slowest resolved impacts, v ~ sqrt(2 a xtol)
  // ~ 4e-5, have times known to xtol / v ~ 2e-5 each.
  const SimulationSummary cvode = Sim(m, zero, zero, 20.0, Integrator::kCvode);
  ASSERT_EQ(cvode.status, SimulationStatus::kFinished) << cvode.message;
  EXPECT_EQ(cvode.sticking_phases, 1);
  EXPECT_NEAR(cvode.first_zeno_time, t_inf, 1e-4);
  EXPECT_NEAR(cvode.final_state[0], 1.0, 1e-9);
}

// Held at the wall by f0 + f cos(w t) - k d = 0.2 + 0.5 cos(2 t) > 0, the mass
// leaves when that force falls through zero: t_r = acos(-0.4) / 2, a phase of
// the forcing no step grid knows.
TEST(ForcedSimulation, HarmonicForcingReleasesTheMassAtTheClosedFormPhase) {
  Model m = MakeChain({1.0}, {1.0}, 0, 1.0, 0.0);
  m.forcing.constant = Eigen::VectorXd::Constant(1, 1.2);
  m.forcing.amplitude = Eigen::VectorXd::Constant(1, 0.5);
  m.forcing.frequency = 2.0;
  const double t_r = std::acos(-0.4) / 2.0;
  const Eigen::VectorXd x0 = Eigen::VectorXd::Constant(1, 1.0), v0 = Eigen::VectorXd::Zero(1);
  const SimulationSummary s = Sim(m, x0, v0, t_r + 0.1);
  ASSERT_EQ(s.status, SimulationStatus::kFinished) << s.message;
  EXPECT_EQ(s.sticking_phases, 1);
  EXPECT_EQ(s.impacts, 0);
  // Released at the root of a smooth function located by Newton: round-off.
  EXPECT_NEAR(s.sticking_time, t_r, 1e-12);
  EXPECT_LT(s.final_state[0], 1.0);
  const SimulationSummary cvode = Sim(m, x0, v0, t_r + 0.1, Integrator::kCvode);
  // CVODE's root finder: 100 ulps of t plus its rtol-level state error.
  EXPECT_NEAR(cvode.sticking_time, t_r, 1e-8);
  // Moreau-Jean sees the release within the step h = 1e-4 that holds it.
  const SimulationSummary mj = Sim(m, x0, v0, t_r + 0.1, Integrator::kMoreauJean, 1e-4);
  EXPECT_NEAR(mj.sticking_time, t_r, 1e-4);
}

// Found by the fuzzer (fuzz/corpus/scene/chatter.toml): a quasi-static force
// pressing m2 into the wall, e = 0.9. The rebounds shrink 0.9x per impact
// until they are lower than the impact search can arm below (2 tol); they
// used to be flown as unarmed micro-flights, each ending tol further out:
// millions of impacts drifting 3.5e-8 past the wall. They must be summed as
// one Zeno sequence, then the mass held.
TEST(ForcedSimulation, AQuasiStaticPushEndsInZenoNotInChatter) {
  Model m = MakeChain({1.2, 1.0}, {0.85, 2.0}, 1, 1.0, 0.9);
  m.damping = ModalDamping(m.mass, m.stiffness, {0.02, 0.02});
  m.forcing.amplitude = Eigen::Vector2d(5.3, 0.0);
  m.forcing.frequency = 1e-6;
  double worst = 0.0;
  SimulateOptions opt;
  opt.t_end = 31.0;
  opt.sample_dt = 0.0;
  opt.max_steps = 100000;
  SimulationObserver obs;
  obs.on_impact = [&](const ContactEvent& ev) { worst = std::max(worst, ev.before[1] - 1.0); };
  const SimulationSummary s = Simulate(m, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), opt, obs);
  ASSERT_EQ(s.status, SimulationStatus::kFinished) << s.message;
  EXPECT_EQ(s.zeno_events, 1);
  EXPECT_LT(s.impacts, 1000);  // 137 measured; the chatter made millions
  // Contacts on the wall to the band's round-off (tol ~ 1e-14 of the forced
  // response's size ~5).
  EXPECT_LT(worst, 1e-12);
}

TEST(ForcedSimulation, ZeroDampingAndForcingGiveTodaysResultsExactly) {
  const Model plain = PaperModel();
  Model zeros = plain;
  zeros.damping = Eigen::Matrix2d::Zero();
  zeros.forcing.constant = Eigen::Vector2d::Zero();
  zeros.forcing.amplitude = Eigen::Vector2d::Zero();
  zeros.forcing.frequency = 0.6;
  const Eigen::VectorXd x0 = Eigen::Vector2d(0.1, 0.5), v0 = Eigen::Vector2d(0.3, 1.0);
  for (Integrator i : {Integrator::kExact, Integrator::kCvode, Integrator::kMoreauJean}) {
    const SimulationSummary a = Sim(plain, x0, v0, 50.0, i), b = Sim(zeros, x0, v0, 50.0, i);
    EXPECT_EQ(a.impacts, b.impacts) << ToString(i);
    EXPECT_EQ(a.final_state, b.final_state) << ToString(i);  // bit for bit
  }
}

TEST(ForcedSimulation, AnUndampedForcedFlightMatchesCvode) {
  Model m = PaperModel();
  m.FirstContact().restitution = 0.9;
  m.forcing.amplitude = Eigen::Vector2d(0.5, 0.0);
  m.forcing.frequency = 1.3;  // between the linear frequencies 0.62 and 2.1
  const Eigen::VectorXd x0 = Eigen::Vector2d(0.5, 0.5), v0 = Eigen::Vector2d(0.5, 1.0);
  const SimulationSummary exact = Sim(m, x0, v0, 100.0);
  const SimulationSummary cvode = Sim(m, x0, v0, 100.0, Integrator::kCvode);
  ASSERT_EQ(exact.status, SimulationStatus::kFinished) << exact.message;
  EXPECT_GT(exact.impacts, 5);
  EXPECT_EQ(cvode.impacts, exact.impacts);
  // No damping: nothing contracts the local errors of CVODE (rtol 1e-10);
  // over ~10 impacts they stay below 1e-6.
  EXPECT_LT((cvode.final_state - exact.final_state).norm(), 1e-6);
}

}  // namespace
}  // namespace nsmodal
