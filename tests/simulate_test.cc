#include <gtest/gtest.h>

#include <cmath>

#include "fixtures.h"
#include "forced_fixtures.h"
#include "nsmodal/admissibility.h"
#include "nsmodal/error.h"
#include "nsmodal/flow.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/simulate.h"
#include "nsmodal/transitions.h"
#include "sim_fixtures.h"

namespace nsmodal {
namespace {

std::vector<double> ImpactTimes(const Model& m, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0,
                                SimulateOptions opt, SimulationSummary* summary = nullptr) {
  std::vector<double> times;
  SimulationObserver obs;
  obs.on_impact = [&](const ContactEvent& ev) { times.push_back(ev.t); };
  opt.sample_dt = 0.0;
  const SimulationSummary s = Simulate(m, x0, v0, opt, obs);
  EXPECT_EQ(s.status, SimulationStatus::kFinished) << s.message;
  if (summary != nullptr) *summary = s;
  return times;
}

SimulateOptions With(Integrator integrator, double t_end) {
  SimulateOptions opt;
  opt.integrator = integrator;
  opt.t_end = t_end;
  opt.rtol = 1e-12;
  opt.atol = 1e-14;
  opt.step = 1e-5;
  return opt;
}

TEST(Simulate, ThreeIntegratorsAgreeOnANonPeriodicTrajectory) {
  // configs/paper-simulate.toml's initial state, 8 impacts in t < 50. The
  // trajectory is sensitive (errors grow ~10x per 10 time units, measured), so
  // the horizon is kept where CVODE's error stays ~1e-7 and Moreau-Jean's
  // first-order error (~h = 1e-5 per impact time) stays ~1e-3.
  const Model m = PaperModel();
  const Eigen::Vector2d x0(0.3, 0.2), v0(1.2, 1.5);
  const std::vector<double> exact = ImpactTimes(m, x0, v0, With(Integrator::kExact, 50.0));
  const std::vector<double> cvode = ImpactTimes(m, x0, v0, With(Integrator::kCvode, 50.0));
  const std::vector<double> mj = ImpactTimes(m, x0, v0, With(Integrator::kMoreauJean, 50.0));
  ASSERT_EQ(exact.size(), 8u);
  ASSERT_EQ(cvode.size(), exact.size());
  ASSERT_EQ(mj.size(), exact.size());
  for (std::size_t k = 0; k < exact.size(); ++k) {
    EXPECT_NEAR(cvode[k], exact[k], 1e-6) << k;
    EXPECT_NEAR(mj[k], exact[k], 5e-3) << k;
  }
}

TEST(Simulate, ExactConservesEnergyForElasticImpacts) {
  const Model m = PaperModel();
  SimulationSummary s;
  ImpactTimes(m, Eigen::Vector2d(0.3, 0.2), Eigen::Vector2d(1.2, 1.5), With(Integrator::kExact, 2000.0), &s);
  EXPECT_GT(s.impacts, 250);
  // Each impact and flight is exact up to round-off of O(1) quantities.
  EXPECT_LT(s.energy_drift, 1e-12);
}

TEST(Simulate, OneImpactOrbitReturnsToItsStartAfterOnePeriod) {
  const Model m = PaperModel();
  const AnalysisBasis b(m);
  for (double period : {5.0, 7.5, 20.0}) {
    const Orbit o = OneImpactOrbit(b, period);
    ASSERT_TRUE(o.admissible);
    // Compare mid-flight, at T + T/2, with the closed form S(T/2) z0: at kT
    // itself the state jumps.
    Eigen::VectorXd y = o.y0;
    Flow(b, period / 2, y);
    const Eigen::VectorXd expect = PhysicalOf(b, y);
    // Tolerances: exact, round-off; cvode at rtol 1e-12 over one period,
    // ~1e-9 measured; Moreau-Jean first order, ~h.
    const std::pair<Integrator, double> cases[] = {
        {Integrator::kExact, 1e-13}, {Integrator::kCvode, 1e-8}, {Integrator::kMoreauJean, 1e-3}};
    for (auto [integrator, tol] : cases) {
      SimulationSummary s;
      ImpactTimes(m, o.z0.head(2), o.z0.tail(2), With(integrator, 1.5 * period), &s);
      EXPECT_EQ(s.impacts, 1) << ToString(integrator) << " T = " << period;
      EXPECT_LT((s.final_state - expect).norm(), tol * expect.norm()) << ToString(integrator) << " T = " << period;
    }
  }
}

TEST(Simulate, ExactStaysOnAStableOrbitForTenThousandPeriods) {
  // T = 7.5 is a stable 1-ipp orbit of the paper's system (a perturbation does
  // not grow); the simulation must stay within the engine's target, 1e-11.
  const Model m = PaperModel();
  const AnalysisBasis b(m);
  const Orbit o = OneImpactOrbit(b, 7.5);
  Eigen::VectorXd y = o.y0;
  Flow(b, 7.5 / 2, y);
  const Eigen::VectorXd expect = PhysicalOf(b, y);
  SimulationSummary s;
  ImpactTimes(m, o.z0.head(2), o.z0.tail(2), With(Integrator::kExact, 10000 * 7.5 + 7.5 / 2), &s);
  EXPECT_EQ(s.impacts, 10000);
  EXPECT_LT((s.final_state - expect).norm(), 1e-11 * expect.norm());
}

TEST(Simulate, GrazingOrbitHasNoMissedOrDuplicatedImpact) {
  // At the grazing transition the 1-ipp orbit touches d twice per period with
  // zero velocity (at t = 1.08 and T - 1.08, the shape of the paper's Fig. 9):
  // over 1.5 periods, one impact and three grazes, never an extra impact.
  // Only 1.5 periods: a grazing orbit is infinitely sensitive (the grazing map
  // has a square-root singularity), so round-off decides the later periods.
  const Model m = PaperModel();
  const AnalysisBasis b(m);
  const std::vector<Transition> tr = OneImpactTransitions(b, 9.0, 9.3, 0.01);
  ASSERT_FALSE(tr.empty());
  ASSERT_EQ(tr.front().kind, TransitionKind::kGrazing);
  const double tg = tr.front().period;
  const Orbit o = OneImpactOrbit(b, tg);
  for (Integrator integrator : {Integrator::kExact, Integrator::kCvode}) {
    SimulationSummary s;
    ImpactTimes(m, o.z0.head(2), o.z0.tail(2), With(integrator, 1.5 * tg), &s);
    EXPECT_EQ(s.impacts, 1) << ToString(integrator);
    EXPECT_EQ(s.grazes, 3) << ToString(integrator);
    EXPECT_EQ(s.sticking_phases, 0) << ToString(integrator);
  }
}

TEST(Simulate, ExactCatchesTheShortExcursionPastGrazing) {
  // Just past the grazing transition the potential orbit crosses d briefly in
  // mid-flight (an excursion ~3.5 (T - T_G) high, ~3.5e-7 here): the exact
  // integrator must see an impact there, before the nominal one at T.
  const Model m = PaperModel();
  const AnalysisBasis b(m);
  const double tg = OneImpactTransitions(b, 9.0, 9.3, 0.01).front().period;
  const double t_bad = OneImpactOrbit(b, tg - 1e-7).admissible ? tg + 1e-7 : tg - 1e-7;
  const Orbit o = OneImpactOrbit(b, t_bad);
  ASSERT_FALSE(o.admissible);
  ASSERT_GT(o.max_excess, 0.0);
  ASSERT_LT(o.max_excess, 1e-6);
  // The orbit is symmetric about T/2: two equal excursions, the first at
  // min(t_max, T - t_max).
  const double t_max = CheckSegment(b, o.y0, t_bad).t_at_max;
  const double t_peak = std::min(t_max, t_bad - t_max);
  const std::vector<double> times =
      ImpactTimes(m, o.z0.head(2), o.z0.tail(2), With(Integrator::kExact, 0.999 * t_bad));
  ASSERT_GE(times.size(), 1u);
  // The first impact is on the rising side of the excursion, whose half-width
  // is sqrt(2 excess / |a_c|) ~ 1e-3.
  EXPECT_LT(times[0], t_peak);
  EXPECT_GT(times[0], t_peak - 1e-2);
}

TEST(Simulate, ZenoAccumulationAndStickingMatchTheClosedFormAndEachOther) {
  const testing::ZenoScene zs;
  const Eigen::Vector2d x0(zs.x0[0], zs.x0[1]), v0(zs.v0[0], zs.v0[1]);
  SimulationSummary exact, cvode, mj;
  ImpactTimes(zs.model, x0, v0, With(Integrator::kExact, 1.0), &exact);
  ImpactTimes(zs.model, x0, v0, With(Integrator::kCvode, 1.0), &cvode);
  ImpactTimes(zs.model, x0, v0, With(Integrator::kMoreauJean, 1.0), &mj);
  // The accumulation time from the geometric series under constant a_2; a_2
  // drifts by ~1e-3 relative over it, so 1e-2 relative is ten times that.
  EXPECT_EQ(exact.zeno_events, 1);
  EXPECT_EQ(cvode.zeno_events, 1);
  EXPECT_NEAR(exact.first_zeno_time, zs.accumulation_time, 1e-2 * zs.accumulation_time);
  EXPECT_NEAR(cvode.first_zeno_time, exact.first_zeno_time, 1e-6);
  // Held until x1 = d: the release time of the closed form (the bounces are
  // ~1e-5 high, so x1 moves as in the held system from t = 0 to ~1e-5).
  EXPECT_EQ(exact.sticking_phases, 1);
  EXPECT_NEAR(exact.first_zeno_time + exact.sticking_time, zs.release_time, 1e-4);
  EXPECT_NEAR(cvode.sticking_time, exact.sticking_time, 1e-6);
  EXPECT_NEAR(mj.sticking_time, exact.sticking_time, 1e-3);  // first order, h = 1e-5, ~70 steps of bounces
  for (const SimulationSummary* s : {&cvode, &mj}) {
    EXPECT_LT((s->final_state - exact.final_state).norm(), 1e-3) << "final states";
  }
  EXPECT_LT(exact.final_state[1], zs.model.FirstContact().gap + 1e-12);  // never beyond the wall
}

TEST(Simulate, PlasticImpactHoldsOrReleases) {
  // e = 0: the contact velocity is zero after the impact; the mass is held
  // while pushed (a_2 > 0) and leaves when a_2 falls through 0.
  Model m = PaperModel();
  m.FirstContact().restitution = 0.0;
  const Eigen::Vector2d x0(1.5, 0.9), v0(0.0, 1.0);
  std::vector<ContactEvent> events;
  SimulationObserver obs;
  obs.on_impact = [&](const ContactEvent& ev) { events.push_back(ev); };
  SimulateOptions opt = With(Integrator::kExact, 3.0);
  const SimulationSummary s = Simulate(m, x0, v0, opt, obs);
  ASSERT_GE(events.size(), 1u);
  EXPECT_NEAR(events[0].after[3], 0.0, 1e-14);
  EXPECT_NEAR(events[0].after[2], events[0].before[2], 1e-14);  // diagonal M: v1 continuous
  EXPECT_EQ(s.zeno_events, 0);
  EXPECT_GE(s.sticking_phases, 1);
  EXPECT_LT(s.final_energy, s.initial_energy);
  SimulationSummary c;
  ImpactTimes(m, x0, v0, With(Integrator::kCvode, 3.0), &c);
  EXPECT_EQ(c.impacts, s.impacts);
  EXPECT_NEAR(c.sticking_time, s.sticking_time, 1e-6);
  EXPECT_LT((c.final_state - s.final_state).norm(), 1e-6);
}

// From 8 modes on the exact integrator's impact search sweeps (first_rise.h).
// A 12-mass chain (unit masses and springs, contact on the last, e = 0.9)
// started off any orbit: the impacts and the end state against the textbook
// modal simulation of forced_fixtures.h (a scan every 0.005 and bisection).
// The two agree to round-off amplified by the motion (measured 3.2e-13
// relative in the end state after 150 time units); 1e-9 leaves room for
// another machine's libm, as the motion amplifies differences impact after
// impact.
TEST(Simulate, ExactWithTheSweepMatchesTheTextbookSimulationOfAChain) {
  constexpr int kMasses = 12;
  const Model m = MakeChain(std::vector<double>(kMasses, 1.0), std::vector<double>(kMasses, 1.0), kMasses - 1, 1.0,
                            0.9);
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(kMasses), v0 = Eigen::VectorXd::Zero(kMasses);
  for (int i = 0; i < kMasses; ++i) v0[i] = std::sin(0.7 * (i + 1)) + 0.5;
  SimulateOptions opt = With(Integrator::kExact, 150.0);
  SimulationSummary s;
  const std::vector<double> times = ImpactTimes(m, x0, v0, opt, &s);
  long impacts = 0;
  const Eigen::VectorXd expected = testing::TextbookSimulator(m).Run(x0, v0, opt.t_end, &impacts);
  EXPECT_GT(s.sweep_steps, 0);
  EXPECT_GT(impacts, 10);
  EXPECT_EQ(s.impacts, impacts);
  EXPECT_LT((s.final_state - expected).norm(), 1e-9 * expected.norm()) << (s.final_state - expected).norm();
}

// A wall the chain never reaches (gap 1e6): the conservative steps, longer
// there than any grid step, cross the flight; the sweep must leave them
// those stretches (swept in steps of at most 64 / w_max it took 3 10^4 grid
// steps here, and a long enough horizon hung).
TEST(Simulate, ExactLeavesAFarWallToTheConservativeSteps) {
  constexpr int kMasses = 10;
  const Model m = MakeChain(std::vector<double>(kMasses, 1.0), std::vector<double>(kMasses, 1.0), kMasses - 1, 1e6,
                            1.0);
  const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(kMasses), v0 = Eigen::VectorXd::Ones(kMasses);
  SimulationSummary s;
  const std::vector<double> times = ImpactTimes(m, x0, v0, With(Integrator::kExact, 1e6), &s);
  EXPECT_TRUE(times.empty());
  EXPECT_EQ(s.sweep_steps, 0);
  EXPECT_LT(s.steps, 1000);  // conservative steps of sqrt(2 d / L2), about 1,400 time units
}

TEST(Simulate, BadInputIsRefusedWithTheField) {
  const Model m = PaperModel();
  auto expect_field = [&](const Eigen::VectorXd& x0, const Eigen::VectorXd& v0, const SimulateOptions& opt,
                          const std::string& field) {
    try {
      Simulate(m, x0, v0, opt);
      ADD_FAILURE() << "no error for " << field;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), field) << e.what();
    }
  };
  const Eigen::Vector2d ok(0.0, 0.5), zero(0.0, 0.0);
  SimulateOptions opt;
  expect_field(Eigen::Vector2d(0.0, 1.2), zero, opt, "simulate.initial_position");  // beyond d
  expect_field(Eigen::Vector3d(0, 0, 0), zero, opt, "simulate.initial_position");
  expect_field(ok, Eigen::Vector3d(0, 0, 0), opt, "simulate.initial_velocity");
  expect_field(Eigen::Vector2d(0.0, NAN), zero, opt, "simulate.initial_position");
  SimulateOptions bad = opt;
  bad.t_end = -1.0;
  expect_field(ok, zero, bad, "simulate.t_end");
  bad = opt;
  bad.rtol = 0.0;
  expect_field(ok, zero, bad, "simulate.rtol");
  bad = opt;
  bad.theta = 0.2;
  expect_field(ok, zero, bad, "simulate.theta");
  bad = opt;
  bad.cvode_method = "rk4";
  expect_field(ok, zero, bad, "simulate.method");
  EXPECT_THROW(ParseIntegrator("euler"), InputError);
}

}  // namespace
}  // namespace nsmodal

namespace nsmodal {
namespace {

TEST(Simulate, MoreauJeanImpactTimesConvergeAtFirstOrder) {
  // Error of the first impact time against the exact integrator, for h from
  // 1e-3 to 1e-5: the observed order log10(e(1e-3) / e(1e-5)) / 2 must be ~1
  // (measured 0.89). The impact is registered at the end of the step whose
  // predicted mid-step gap is closed, so its time is within ~2h of the true one
  // (measured 0.8h and 1.4h).
  const Model m = PaperModel();
  const Eigen::Vector2d x0(0.3, 0.2), v0(1.2, 1.5);
  auto first = [&](Integrator integrator, double h) {
    SimulateOptions opt;
    opt.integrator = integrator;
    opt.step = h;
    opt.t_end = 2.0;
    opt.sample_dt = 0.0;
    double t1 = -1.0;
    SimulationObserver obs;
    obs.on_impact = [&](const ContactEvent& ev) {
      if (t1 < 0.0) t1 = ev.t;
    };
    Simulate(m, x0, v0, opt, obs);
    return t1;
  };
  const double ref = first(Integrator::kExact, 1e-3);
  const double e3 = std::abs(first(Integrator::kMoreauJean, 1e-3) - ref);
  const double e5 = std::abs(first(Integrator::kMoreauJean, 1e-5) - ref);
  EXPECT_LE(e3, 2e-3);
  EXPECT_LE(e5, 2e-5);
  const double order = std::log10(e3 / e5) / 2.0;
  EXPECT_GT(order, 0.7);
  EXPECT_LT(order, 1.3);
}

// Issue 14: CVODE's energy error per flight became a phase drift growing as
// K^2 on a non-isochronous family (1.1e-6, 1.1e-4, 1.1e-2 after 100, 1000,
// 10000 periods of the stable 1-ipp orbit T = 7.5 at rtol 1e-10). With the
// state put back on the energy level once it drifts past 100 rtol E0 the
// error grows at most linearly: measured 3.4e-7 after 100 periods, 3.8e-6
// after 1000, 3.7e-5 after 10000 (x11, x10; linear growth is x10, quadratic
// x100, so x20 separates them).
TEST(Cvode, ErrorGrowsAtMostLinearlyOnAStableOrbit) {
  const Model m = PaperModel();
  const AnalysisBasis b(m);
  const double period = 7.5;
  const Orbit o = OneImpactOrbit(b, period);
  Eigen::VectorXd y = o.y0;
  Flow(b, 0.5 * period, y);  // mid-flight: the comparison times meet no impact
  const Eigen::VectorXd mid = PhysicalOf(b, y);
  auto error_after = [&](int periods, bool projection) {
    SimulateOptions opt;
    opt.integrator = Integrator::kCvode;
    opt.rtol = 1e-10;
    opt.atol = 1e-12;
    opt.sample_dt = 0.0;
    opt.t_end = periods * period;
    opt.cvode_energy_projection = projection;
    const SimulationSummary s = Simulate(m, mid.head(2), mid.tail(2), opt);
    return (s.final_state - mid).norm() / mid.norm();
  };
  const double e100 = error_after(100, true), e1000 = error_after(1000, true);
  EXPECT_LT(e1000 / e100, 20.0) << e100 << " -> " << e1000;
  EXPECT_LT(e1000, 1e-5);
  // Without the projection: the quadratic growth this fixes (x98 measured).
  EXPECT_GT(error_after(1000, false) / error_after(100, false), 50.0);
}

}  // namespace
}  // namespace nsmodal
