// Periodic forced responses (forced_orbit.h) against a closed form, the
// energy balance and the simulator.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "forced_fixtures.h"
#include "nsmodal/error.h"
#include "nsmodal/forced_orbit.h"
#include "nsmodal/simulate.h"

namespace nsmodal {
namespace {

using testing::DampedForcedPaper;

// The (1,1) orbit of x'' + x = F cos(w t), impact at x = d with e < 1
// (undamped, omega = 1). With X = F / (1 - w^2), x_p = X cos(w t), and
// the impact at phase phi = w t1, let delta = d - X cos(phi) and
// a = -X w sin(phi) (the particular solution's velocity). The homogeneous
// part h = x - x_p rotates by omega P over the period P = 2 pi / w; writing
// h = delta at both ends with velocities u (after) and u' (before), and
// u = -e v- - a, u' = v- - a, the rotation's two rows give
//   u = delta (1 - cos P) / sin P,   u' = -delta sin P + cos P u,
// and eliminating v-:  delta (1 - cos P)(1 - e) / sin P = -(1 + e) a, i.e.
//   X (cos phi + kappa w sin phi) = d,  kappa = (1 + e) cot(P / 2) / (1 - e),
// two phases phi = psi +- acos(d / (X sqrt(1 + kappa^2 w^2))), psi = atan2(kappa w, 1),
// with the impact velocity v- = -(u + a) / e.
TEST(ForcedOrbit, OneDofOneOneOrbitMatchesTheClosedForm) {
  const double e = 0.8, d = 1.0, force = 1.5, w = 0.7;
  Model m = MakeChain({1.0}, {1.0}, 0, d, e);
  m.forcing.amplitude = Eigen::VectorXd::Constant(1, force);
  m.forcing.frequency = w;
  const double p = 2.0 * M_PI / w, x = force / (1.0 - w * w);
  const double kappa = (1.0 + e) / std::tan(p / 2.0) / (1.0 - e);
  const double psi = std::atan2(kappa * w, 1.0);
  const double spread = std::acos(d / (x * std::sqrt(1.0 + kappa * kappa * w * w)));
  const ForcedProblem problem(m, 1, 1, w, force);
  const std::vector<Eigen::VectorXd> found = problem.FindAll();
  ASSERT_EQ(found.size(), 2u);
  for (double phi : {psi + spread, psi - spread}) {
    const double wrapped = phi - 2.0 * M_PI * std::floor(phi / (2.0 * M_PI));
    const auto it = std::find_if(found.begin(), found.end(), [&](const Eigen::VectorXd& u) {
      return std::abs(std::remainder(u[0] - wrapped, 2.0 * M_PI)) < 1e-6;
    });
    ASSERT_NE(it, found.end()) << "phase " << wrapped;
    // Newton converges to the residual's round-off (x_c to 1e-13 d): the
    // phase to 1e-13 / |dx_c/dphi|, of order 1e-13 here.
    EXPECT_NEAR(std::remainder((*it)[0] - wrapped, 2.0 * M_PI), 0.0, 1e-12);
    const ForcedOrbit o = problem.Orbit(*it);
    const double delta = d - x * std::cos(wrapped), a = -x * w * std::sin(wrapped);
    const double u = delta * (1.0 - std::cos(p)) / std::sin(p);
    EXPECT_NEAR(o.before[0][1], -(u + a) / e, 1e-11);
    EXPECT_NEAR(o.after[0][1], (u + a), 1e-11);
  }
}

// Over one period of a forced periodic orbit the energy returns: the work of
// the force equals the energy dissipated by damping plus the energy lost at
// the impacts.
TEST(ForcedOrbit, EnergyBalanceOverAPeriod) {
  for (double e : {0.8, 1.0}) {
    Model m = DampedForcedPaper();
    m.FirstContact().restitution = e;
    const ForcedProblem problem(m, 1, 1, m.forcing.frequency, 0.3);
    const std::vector<Eigen::VectorXd> found = problem.FindAll();
    ASSERT_FALSE(found.empty()) << "e = " << e;
    for (const Eigen::VectorXd& u : found) {
      const ForcedOrbit o = problem.Orbit(u);
      EXPECT_GT(o.work, 0.0);
      if (e == 1.0) {
        EXPECT_NEAR(o.impact_loss, 0.0, 1e-14 * o.energy);
      }
      // Quadrature exact to round-off on smooth panels: 1e-10 of the work.
      EXPECT_NEAR(o.work, o.dissipated + o.impact_loss, 1e-10 * o.work) << "e = " << e;
    }
  }
}

TEST(ForcedOrbit, TheSimulatorReturnsAfterOnePeriod) {
  const Model m = DampedForcedPaper();
  for (int n : {1, 2}) {
    const ForcedProblem problem(m, 1, n, m.forcing.frequency, 0.3);
    const std::vector<Eigen::VectorXd> found = problem.FindAll();
    ASSERT_FALSE(found.empty()) << "n = " << n;
    for (const Eigen::VectorXd& u : found) {
      const ForcedOrbit o = problem.Orbit(u);
      if (!o.admissible) continue;  // the simulator follows only admissible ones
      const Eigen::VectorXd z0 = problem.StateAt(o, 0.0);
      SimulateOptions opt;
      opt.t_end = o.period;
      opt.sample_dt = 0.0;
      const SimulationSummary s = Simulate(m, z0.head(2), z0.tail(2), opt);
      EXPECT_EQ(s.impacts, 1) << "n = " << n;
      // The target: back to the start after one period to 1e-9.
      EXPECT_LT((s.final_state - z0).norm(), 1e-9) << "n = " << n;
    }
  }
}

// The saltation matrices (time-dependent field) against finite differences
// of the exact simulator's period map.
TEST(ForcedOrbit, MultipliersMatchFiniteDifferencesOfTheSimulator) {
  const Model m = DampedForcedPaper();
  const ForcedProblem problem(m, 1, 1, m.forcing.frequency, 0.3);
  int checked = 0;
  for (const Eigen::VectorXd& u : problem.FindAll()) {
    const ForcedOrbit o = problem.Orbit(u);
    if (!o.admissible) continue;
    const Eigen::VectorXd z0 = problem.StateAt(o, 0.0);
    SimulateOptions opt;
    opt.t_end = o.period;
    opt.sample_dt = 0.0;
    // Central differences with h = 1e-6: truncation ~h^2 |second derivative|,
    // round-off ~1e-16 / h: ~1e-8 in each entry.
    const double h = 1e-6;
    Eigen::MatrixXd j(4, 4);
    for (int k = 0; k < 4; ++k) {
      Eigen::VectorXd zp = z0, zm = z0;
      zp[k] += h;
      zm[k] -= h;
      const Eigen::VectorXd fp = Simulate(m, zp.head(2), zp.tail(2), opt).final_state;
      const Eigen::VectorXd fm = Simulate(m, zm.head(2), zm.tail(2), opt).final_state;
      j.col(k) = (fp - fm) / (2.0 * h);
    }
    Eigen::VectorXd fd = j.eigenvalues().cwiseAbs(), an = o.multipliers.cwiseAbs();
    std::sort(fd.data(), fd.data() + fd.size());
    std::sort(an.data(), an.data() + an.size());
    EXPECT_LT((fd - an).cwiseAbs().maxCoeff(), 1e-6) << fd.transpose() << " vs " << an.transpose();
    ++checked;
  }
  EXPECT_GT(checked, 0);
}

TEST(ForcedOrbit, ALongSimulationSettlesOnTheStableAdmissibleOrbit) {
  const Model m = DampedForcedPaper();
  const ForcedProblem problem(m, 1, 1, m.forcing.frequency, 0.3);
  std::vector<ForcedOrbit> stable;
  for (const Eigen::VectorXd& u : problem.FindAll()) {
    const ForcedOrbit o = problem.Orbit(u);
    if (o.admissible && o.stable) stable.push_back(o);
  }
  ASSERT_EQ(stable.size(), 1u);
  SimulateOptions opt;
  opt.t_end = 400 * stable[0].period;
  opt.sample_dt = 0.0;
  const SimulationSummary s = Simulate(m, Eigen::Vector2d(0.2, -0.1), Eigen::Vector2d(0.0, 0.3), opt);
  // The transient decays like max |multiplier|^k: 0.93^400 ~ 1e-13 of its start.
  EXPECT_LT((s.final_state - problem.StateAt(stable[0], opt.t_end)).norm(), 1e-9)
      << "max multiplier " << stable[0].max_multiplier;
}

TEST(ForcedOrbit, BadRequestsNameTheFieldAndValue) {
  const Model m = DampedForcedPaper();
  auto expect = [](auto&& make, const std::string& field, const std::string& value) {
    try {
      make();
      FAIL() << "no error for " << field;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), field) << e.what();
      EXPECT_NE(std::string(e.what()).find(value), std::string::npos) << e.what();
    }
  };
  expect([&] { ForcedProblem(m, 0, 1, 0.5, 0.3); }, "impacts", "0");
  expect([&] { ForcedProblem(m, 9, 1, 0.5, 0.3); }, "impacts", "9");
  expect([&] { ForcedProblem(m, 1, 0, 0.5, 0.3); }, "periods", "0");
  expect([&] { ForcedProblem(m, 1, 1, 0.0, 0.3); }, "forcing.frequency", "0");
  expect([&] { ForcedProblem(m, 1, 1, -1.0, 0.3); }, "forcing.frequency", "-1");
  expect([&] { ForcedProblem(m, 1, 1, 0.5, -0.25); }, "forcing.amplitude", "-0.25");
  // A response period beyond 1e5 shortest linear periods: NC3 and the
  // quadrature would scan more than 1e5 oscillations per flight.
  expect([&] { ForcedProblem(m, 1, 1, 1e-6, 0.3); }, "forcing.frequency", "response period of 6283185");
  // Measured in the flow's fastest time scale, not the undamped period: an
  // overdamped oscillator (omega = 1, zeta = 1e4) decays at |lambda| ~ 2e4, so
  // a period of 6283 (1e3 undamped periods, allowed by that measure) is 1.3e8
  // of its time scales: the quadrature alone would take 1.6e8 panels.
  Model overdamped = MakeChain({1.0}, {1.0}, 0, 1.0, 0.8);
  overdamped.damping = Eigen::MatrixXd::Constant(1, 1, 2e4);
  overdamped.forcing.amplitude = Eigen::VectorXd::Constant(1, 1.0);
  overdamped.forcing.frequency = 1e-3;
  expect([&] { ForcedProblem(overdamped, 1, 1, 1e-3, 1.0); }, "forcing.frequency", "response period of 6283.18");
  Model free = PaperModel();
  expect([&] { ForcedProblem(free, 1, 1, 0.5, 0.3); }, "forcing.amplitude", "harmonic");
  free.forcing.amplitude = Eigen::Vector2d(1.0, 0.0);
  free.forcing.frequency = 0.5;
  expect([&] { ForcedProblem(free, 1, 1, 0.5, 0.3); }, "system", "e = 1");
}

}  // namespace
}  // namespace nsmodal
