// Several contacts (issue 24): the model's contacts and their checks, the
// three integrators against closed forms with two walls, a second contact
// out of reach, simultaneous impacts (decoupled and by the LCP), Zeno and
// sticking per contact.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "nsmodal/admissibility.h"
#include "nsmodal/contact.h"
#include "nsmodal/error.h"
#include "nsmodal/lcp.h"
#include "nsmodal/modal_basis.h"
#include "nsmodal/model_spec.h"
#include "nsmodal/scene.h"
#include "nsmodal/flow.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/simulate.h"
#include "nsmodal/stability.h"
#include "nsmodal/transitions.h"
#include "nsmodal/two_impact.h"

namespace nsmodal {
namespace {

// A mass m on a spring k between two walls, x <= d_up and x >= -d_low.
Model Clearance(double d_up, double d_low, double e_up, double e_low, double m = 1.0, double k = 4.0) {
  Model model = MakeChain({m}, {k}, 0, d_up, e_up);
  model.contacts = {DofContact(1, 0, true, d_up, e_up), DofContact(1, 0, false, d_low, e_low)};
  Validate(model);
  return model;
}

struct Trace {
  SimulationSummary summary;
  std::vector<ContactEvent> impacts;
};

Trace SimulateTrace(const Model& m, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0, Integrator integrator,
             double t_end, double rtol = 1e-12, double step = 1e-5) {
  SimulateOptions opt;
  opt.integrator = integrator;
  opt.t_end = t_end;
  opt.sample_dt = 0.0;
  opt.rtol = rtol;
  opt.atol = 1e-2 * rtol;
  opt.step = step;
  Trace run;
  SimulationObserver obs;
  obs.on_impact = [&](const ContactEvent& ev) { run.impacts.push_back(ev); };
  run.summary = nsmodal::Simulate(m, x0, v0, opt, obs);
  EXPECT_EQ(run.summary.status, SimulationStatus::kFinished) << run.summary.message;
  return run;
}

// The alternating orbit of a mass between walls at +-d: from x = 0 with
// speed v, a cosine of amplitude A = sqrt(2E/k) > d between impacts, so the
// flight from one wall to the other lasts (pi - 2 arccos(d / A)) / w and the
// period is twice that: T(E) = 2 (pi - 2 arccos(d / sqrt(2 E / k))) / w.
TEST(Contacts, MassBetweenTwoWallsKeepsTheAlternatingOrbitsPeriodEnergyRelation) {
  const double k = 4.0, d = 0.5, w = std::sqrt(k);
  const Model m = Clearance(d, d, 1.0, 1.0, 1.0, k);
  for (double v : {1.2, 3.0, 10.0}) {
    const double energy = 0.5 * v * v, amplitude = std::sqrt(2.0 * energy / k);
    const double half = (M_PI - 2.0 * std::acos(d / amplitude)) / w;
    for (Integrator integrator : {Integrator::kExact, Integrator::kCvode}) {
      const Trace r = SimulateTrace(m, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, v), integrator, 40.0);
      ASSERT_GT(r.impacts.size(), 10u);
      for (std::size_t i = 1; i < r.impacts.size(); ++i) {
        // Walls alternate, each flight lasts half the period. Exact: the
        // search's root_tol 1e-14 on times of order 40 leaves ~1e-12 of
        // accumulated round-off; CVODE at rtol 1e-12: ~1e-9 per flight.
        EXPECT_NE(r.impacts[i].contact, r.impacts[i - 1].contact) << i;
        const double tol = integrator == Integrator::kExact ? 1e-11 : 1e-8;
        EXPECT_NEAR(r.impacts[i].t - r.impacts[i - 1].t, half, tol) << ToString(integrator) << " v " << v << " " << i;
      }
      EXPECT_EQ(r.summary.impacts_per_contact.size(), 2u);
      EXPECT_LE(std::abs(r.summary.impacts_per_contact[0] - r.summary.impacts_per_contact[1]), 1);
      EXPECT_NEAR(r.summary.final_energy, energy, 1e-9 * energy);
    }
  }
}

// Walls at +1 and -2: the upper wall's one-impact orbits (a cosine of
// amplitude A from x = 1 back to x = 1) stay clear of the lower wall while
// A < 2 and graze it at A = 2; above, both walls are struck.
TEST(Contacts, EachWallsOneImpactOrbitGrazesTheOtherWallWhereTheClosedFormSays) {
  const double k = 1.0, up = 1.0, low = 2.0;
  const Model m = Clearance(up, low, 1.0, 1.0, 1.0, k);
  for (double amplitude : {1.5, 1.999, 2.001, 3.0}) {
    const double v = amplitude * std::sqrt(k);  // from x = 0: E = v^2 / 2 = k A^2 / 2
    const Trace r = SimulateTrace(m, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, v), Integrator::kExact, 200.0);
    EXPECT_GT(r.summary.impacts_per_contact[0], 20) << amplitude;
    if (amplitude < low) {
      EXPECT_EQ(r.summary.impacts_per_contact[1], 0) << amplitude;
    } else {
      EXPECT_GT(r.summary.impacts_per_contact[1], 20) << amplitude;
    }
  }
}

// A second contact out of reach changes nothing: the same impacts at the
// same times, the same final state, to the last bit (the searches of the
// other contact do not touch the state; CVODE's root functions do not move
// its steps; Moreau-Jean's LCP has one active contact).
TEST(Contacts, ASecondContactOutOfReachReproducesTheOneContactResultsExactly) {
  const Model one = PaperModel();
  Model two = one;
  two.contacts.push_back(DofContact(2, 0, false, 1e3, 0.7));  // x1 >= -1000: never reached
  two.FirstContact().shorthand = false;
  Validate(two);
  const Eigen::Vector2d x0(0.3, 0.2), v0(1.2, 1.5);
  for (Integrator integrator : {Integrator::kExact, Integrator::kCvode, Integrator::kMoreauJean}) {
    const Trace a = SimulateTrace(one, x0, v0, integrator, 60.0, 1e-10, 1e-4);
    const Trace b = SimulateTrace(two, x0, v0, integrator, 60.0, 1e-10, 1e-4);
    ASSERT_EQ(a.impacts.size(), b.impacts.size()) << ToString(integrator);
    for (std::size_t i = 0; i < a.impacts.size(); ++i) {
      EXPECT_EQ(a.impacts[i].t, b.impacts[i].t) << ToString(integrator) << " " << i;
      EXPECT_EQ(b.impacts[i].contact, 0);
    }
    EXPECT_TRUE(a.summary.final_state == b.summary.final_state) << ToString(integrator);
    EXPECT_EQ(b.summary.impacts_per_contact, (std::vector<long>{a.summary.impacts, 0}));
  }
}

// Two identical, uncoupled oscillators with a stop each, started alike:
// both walls are struck at the same instant. The Delassus matrix is
// diagonal, so each takes its own law (here e = 1 and e = 0.5): each mass
// moves exactly as it would alone.
TEST(Contacts, DecoupledSimultaneousImpactsEachTakeTheirOwnLaw) {
  Model two = MakeChain({1.0, 1.0}, {1.0, 0.0}, 0, 1.0, 1.0);
  two.stiffness = Eigen::Matrix2d::Identity();  // two springs to ground, no coupling
  two.contacts = {DofContact(2, 0, true, 1.0, 1.0), DofContact(2, 1, true, 1.0, 0.5)};
  Validate(two);
  const Model alone_elastic = MakeChain({1.0}, {1.0}, 0, 1.0, 1.0), alone_lossy = MakeChain({1.0}, {1.0}, 0, 1.0, 0.5);
  const Eigen::Vector2d x0(0.0, 0.0), v0(2.0, 2.0);
  for (Integrator integrator : {Integrator::kExact, Integrator::kCvode}) {
    const Trace both = SimulateTrace(two, x0, v0, integrator, 10.0);
    const Trace a = SimulateTrace(alone_elastic, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, 2.0), integrator, 10.0);
    const Trace b = SimulateTrace(alone_lossy, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, 2.0), integrator, 10.0);
    // Every impact of each mass is counted on its contact, simultaneous or
    // not: as many as each mass alone has.
    EXPECT_EQ(both.summary.impacts_per_contact, (std::vector<long>{a.summary.impacts, b.summary.impacts}))
        << ToString(integrator);
    EXPECT_EQ(both.summary.impacts, a.summary.impacts + b.summary.impacts);
    // The first impact is simultaneous: both contacts' laws at once.
    ASSERT_GE(both.impacts.size(), 2u);
    EXPECT_EQ(both.impacts[0].t, both.impacts[1].t);
    const Eigen::VectorXd& after = both.impacts[0].after;
    EXPECT_NEAR(after[2], a.impacts[0].after[1], 1e-9) << ToString(integrator);
    EXPECT_NEAR(after[3], b.impacts[0].after[1], 1e-9) << ToString(integrator);
    // Then each mass as alone (CVODE: its tolerance over 10 time units).
    const double tol = integrator == Integrator::kExact ? 1e-12 : 1e-7;
    EXPECT_NEAR(both.summary.final_state[0], a.summary.final_state[0], tol);
    EXPECT_NEAR(both.summary.final_state[1], b.summary.final_state[0], tol);
    EXPECT_NEAR(both.summary.final_state[2], a.summary.final_state[1], tol);
    EXPECT_NEAR(both.summary.final_state[3], b.summary.final_state[1], tol);
  }
}

// Coupled walls (a coupled M: the Delassus matrix is full): Moreau's law by
// the LCP. Where an impulse acts the contact leaves at -e u-; where none
// acts it does not approach faster than -e u- allows; impulses >= 0.
TEST(Contacts, CoupledSimultaneousImpactsSatisfyMoreausLaw) {
  Model m;
  m.mass.resize(2, 2);
  m.mass << 2.0, 0.8, 0.8, 1.0;
  m.stiffness = Eigen::Matrix2d::Identity();
  m.contacts = {DofContact(2, 0, true, 1.0, 0.9), DofContact(2, 1, true, 1.0, 0.4)};
  Validate(m);
  const ContactModel cm(m);
  ASSERT_GT(std::abs(cm.delassus(0, 1)), 0.1);
  for (const Eigen::Vector2d& v : {Eigen::Vector2d(1.0, 1.0), Eigen::Vector2d(3.0, 0.1), Eigen::Vector2d(0.1, 3.0)}) {
    Eigen::VectorXd after = v;
    ASSERT_TRUE(cm.ApplyImpacts({0, 1}, after));
    // The impulses, from M (v+ - v-) = -H' p with H = I here.
    const Eigen::Vector2d p = -(m.mass * (after - v));
    for (int j = 0; j < 2; ++j) {
      const double e = m.contacts[j].restitution, slack = -(after[j] + e * v[j]);
      const double kTol = 1e-12 * v.norm();  // an LCP solved by pivoting: round-off of the velocities
      EXPECT_GE(p[j], -kTol) << j;
      EXPECT_GE(slack, -kTol) << j;
      EXPECT_LE(std::abs(p[j] * slack), kTol * std::max(1.0, p.norm())) << j;
    }
  }
  // The LCP solver on its own: a problem with a known solution, then random
  // SPD problems of 2 to 6 unknowns against the enumeration of all 2^n
  // index sets (the unique solution of an SPD LCP is the one set whose block
  // solve gives z >= 0 and w >= 0). Tolerance: both solve the same blocks,
  // round-off of an O(1) system, 1e-12.
  std::srand(7);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 2 + trial % 5;
    const Eigen::MatrixXd r = Eigen::MatrixXd::Random(n, n);
    const Eigen::MatrixXd g = r * r.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n);
    const Eigen::VectorXd q = Eigen::VectorXd::Random(n);
    const LcpSolution sol = SolveLcp(g, q);
    ASSERT_TRUE(sol.solved) << sol.message;
    int found = 0;
    for (int mask = 0; mask < (1 << n); ++mask) {
      Eigen::VectorXd z = Eigen::VectorXd::Zero(n);
      std::vector<int> idx;
      for (int i = 0; i < n; ++i) {
        if (mask & (1 << i)) idx.push_back(i);
      }
      const int k = static_cast<int>(idx.size());
      Eigen::MatrixXd block(k, k);
      Eigen::VectorXd rhs(k);
      for (int a_i = 0; a_i < k; ++a_i) {
        rhs[a_i] = -q[idx[a_i]];
        for (int b_i = 0; b_i < k; ++b_i) block(a_i, b_i) = g(idx[a_i], idx[b_i]);
      }
      if (k > 0) {
        const Eigen::VectorXd zb = block.ldlt().solve(rhs);
        for (int a_i = 0; a_i < k; ++a_i) z[idx[a_i]] = zb[a_i];
      }
      const Eigen::VectorXd w = g * z + q;
      bool ok = z.minCoeff() >= -1e-12;
      for (int i = 0; i < n; ++i) ok = ok && ((mask & (1 << i)) || w[i] >= -1e-12);
      if (ok) {
        ++found;
        EXPECT_LE((z - sol.z).cwiseAbs().maxCoeff(), 1e-12) << trial;
      }
    }
    EXPECT_GE(found, 1) << trial;
  }
  // Dependent normals: a singular Delassus matrix is refused, not guessed.
  Eigen::Matrix2d singular;
  singular << 1.0, 1.0, 1.0, 1.0;
  EXPECT_FALSE(SolveLcp(singular, Eigen::Vector2d(-1.0, -2.0)).solved);
  // A problem with a known solution.
  Eigen::Matrix2d a;
  a << 2.0, 1.0, 1.0, 2.0;
  const LcpSolution s = SolveLcp(a, Eigen::Vector2d(-1.0, -1.0));
  ASSERT_TRUE(s.solved) << s.message;
  EXPECT_NEAR(s.z[0], 1.0 / 3.0, 1e-14);
  EXPECT_NEAR(s.z[1], 1.0 / 3.0, 1e-14);
}

// The paper's chain with a two-sided stop on x2 (x2 <= 1, x2 >= -0.8) and
// lossy impacts: the three integrators strike the same walls at the same
// times (tolerances as Simulate.ThreeIntegratorsAgreeOnANonPeriodicTrajectory:
// CVODE at rtol 1e-12, Moreau-Jean's first order at h = 1e-5).
TEST(Contacts, ThreeIntegratorsAgreeOnATwoSidedStop) {
  Model m = PaperModel();
  m.contacts = {DofContact(2, 1, true, 1.0, 0.9), DofContact(2, 1, false, 0.8, 0.8)};
  Validate(m);
  const Eigen::Vector2d x0(0.3, 0.2), v0(1.2, 1.5);
  const Trace exact = SimulateTrace(m, x0, v0, Integrator::kExact, 40.0);
  const Trace cvode = SimulateTrace(m, x0, v0, Integrator::kCvode, 40.0);
  const Trace mj = SimulateTrace(m, x0, v0, Integrator::kMoreauJean, 40.0);
  ASSERT_GE(exact.impacts.size(), 8u);
  ASSERT_GT(exact.summary.impacts_per_contact[0], 0);
  ASSERT_GT(exact.summary.impacts_per_contact[1], 0);
  ASSERT_EQ(cvode.impacts.size(), exact.impacts.size());
  ASSERT_EQ(mj.impacts.size(), exact.impacts.size());
  for (std::size_t i = 0; i < exact.impacts.size(); ++i) {
    EXPECT_EQ(cvode.impacts[i].contact, exact.impacts[i].contact) << i;
    EXPECT_EQ(mj.impacts[i].contact, exact.impacts[i].contact) << i;
    EXPECT_NEAR(cvode.impacts[i].t, exact.impacts[i].t, 1e-6) << i;
    EXPECT_NEAR(mj.impacts[i].t, exact.impacts[i].t, 5e-3) << i;
  }
}

// A mass pushed down onto the lower wall (a constant force) with e = 0.5:
// a Zeno sequence on contact 2, then it rests there; contact 1 is never struck.
TEST(Contacts, ZenoAndStickingAreCountedPerContact) {
  Model m = Clearance(1.0, 0.5, 0.5, 0.5);
  m.forcing.constant = Eigen::VectorXd::Constant(1, -4.0);  // static position -1, beyond the lower wall
  Validate(m);
  for (Integrator integrator : {Integrator::kExact, Integrator::kCvode}) {
    const Trace r = SimulateTrace(m, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1), integrator, 20.0, 1e-10);
    EXPECT_EQ(r.summary.impacts_per_contact[0], 0) << ToString(integrator);
    EXPECT_GT(r.summary.impacts_per_contact[1], 3) << ToString(integrator);
    EXPECT_EQ(r.summary.zeno_per_contact, (std::vector<long>{0, 1})) << ToString(integrator);
    EXPECT_EQ(r.summary.sticking_per_contact, (std::vector<long>{0, 1})) << ToString(integrator);
    // Held on the lower wall at the end.
    EXPECT_NEAR(r.summary.final_state[0], -0.5, 1e-9) << ToString(integrator);
  }
}

// Two masses on springs pushed down onto their own lower walls (a constant
// force; e = 0.5): mass 2, released higher, bounces on its wall while mass 1
// already rests on its own. Each comes to rest (a Zeno sequence each), and
// both are held together to the end: several contacts held at once. A
// bounce of mass 2 leaves mass 1 on its wall (one sticking phase each).
// The three integrators agree on the time spent held: Moreau-Jean to its
// first order (a few h = 1e-5 per phase), CVODE to its resolution.
TEST(Contacts, TwoContactsHeldAtOnce) {
  Model m;
  m.mass = Eigen::Matrix2d::Identity();
  m.stiffness = Eigen::Matrix2d::Identity();
  m.contacts = {DofContact(2, 0, false, 0.5, 0.5), DofContact(2, 1, false, 0.5, 0.5)};
  m.forcing.constant = Eigen::Vector2d(-2.0, -2.0);  // static positions -2: beyond both walls
  Validate(m);
  const Eigen::Vector2d x0(-0.5, 0.1), v0(0.0, 0.0);
  const Trace exact = SimulateTrace(m, x0, v0, Integrator::kExact, 10.0);
  const Trace cvode = SimulateTrace(m, x0, v0, Integrator::kCvode, 10.0, 1e-10);
  const Trace mj = SimulateTrace(m, x0, v0, Integrator::kMoreauJean, 10.0, 1e-10, 1e-5);
  for (const Trace* t : {&exact, &cvode}) {
    EXPECT_EQ(t->summary.sticking_per_contact, (std::vector<long>{1, 1}));
    EXPECT_NEAR(t->summary.final_state[0], -0.5, 1e-9);
    EXPECT_NEAR(t->summary.final_state[1], -0.5, 1e-9);
    EXPECT_NEAR(t->summary.final_state[2], 0.0, 1e-9);
    EXPECT_NEAR(t->summary.final_state[3], 0.0, 1e-9);
  }
  // Held time: mass 1 from t = 0, mass 2 from its accumulation point.
  EXPECT_NEAR(cvode.summary.sticking_time, exact.summary.sticking_time, 1e-6);
  EXPECT_NEAR(mj.summary.sticking_time, exact.summary.sticking_time, 1e-3);
  EXPECT_NEAR(mj.summary.final_state[1], -0.5, 1e-4);
}

// A relative contact (an impact damper's cavity): a free mass m2 rattling
// between walls x1 - x2 <= g and x2 - x1 <= g of a primary mass m1 on a
// spring. Momentum exchange at each e = 1 impact conserves the energy; K is
// semi-definite only through the free mass (its spring is zero).
TEST(Contacts, AnImpactDampersCavityConservesEnergyWithElasticImpacts) {
  Model m = MakeChain({1.0, 0.2}, {1.0, 0.0}, 0, 1.0, 1.0);
  m.contacts = {BetweenContact(2, 0, 1, 0.1, 1.0), BetweenContact(2, 1, 0, 0.1, 1.0)};
  Validate(m);
  for (Integrator integrator : {Integrator::kExact, Integrator::kCvode}) {
    const Trace r = SimulateTrace(m, Eigen::Vector2d(1.0, 1.0), Eigen::Vector2d::Zero(), integrator, 30.0);
    EXPECT_GT(r.summary.impacts_per_contact[0], 2) << ToString(integrator);
    EXPECT_GT(r.summary.impacts_per_contact[1], 2) << ToString(integrator);
    EXPECT_NEAR(r.summary.energy_drift, 0.0, integrator == Integrator::kExact ? 1e-12 : 1e-8);
    // Total momentum m1 v1 + m2 v2 is continuous across each impact: to
    // round-off for the exact law; CVODE's energy projection (simulate.h)
    // rescales the velocities after an impact by up to 100 rtol = 1e-10 of
    // the energy, which moves the momentum by as much.
    const double kMomentumTol = integrator == Integrator::kExact ? 1e-12 : 1e-9;
    for (const ContactEvent& ev : r.impacts) {
      EXPECT_NEAR(ev.before[2] + 0.2 * ev.before[3], ev.after[2] + 0.2 * ev.after[3], kMomentumTol);
    }
  }
}

// Nonsmooth modes with two contacts (e = 1). A mass (k, m = 1) between walls
// x <= d1 and x >= -d2. The 1-ipp family of the upper wall is
// x(t) = d1 cos(w (t - T/2)) / cos(w T / 2): for pi < w T < 2 pi it dips to
// -d1 / |cos(w T / 2)|, an amplitude falling from infinity to d1 as T grows,
// so it clears the lower wall for T above the graze |cos(w T / 2)| = d1 / d2. The alternating orbit (1, 2) of amplitude A flies from d1 to -d2
// in (pi - acos(d1 / A) - acos(d2 / A)) / w and back in as long: t2 = T / 2,
// T = 2 (pi - acos(d1 / A) - acos(d2 / A)) / w.
TEST(ContactsAnalysis, OneWallsFamilyAndTheAlternatingOrbitMatchTheirClosedForms) {
  const double k = 4.0, w = 2.0, d1 = 1.0, d2 = 1.5;
  const AnalysisBasis b(Clearance(d1, d2, 1.0, 1.0, 1.0, k));
  // Sequence (1): the energy of the closed form, admissible until the graze.
  const double graze = 2.0 * (M_PI - std::acos(d1 / d2)) / w;
  for (double period : {1.8, 2.0, 2.2, 2.4}) {
    const Orbit o = OneImpactOrbit(b, period, {}, 0);
    const double amplitude = d1 / std::abs(std::cos(0.5 * w * period));
    ASSERT_TRUE(o.potential) << period << ": " << o.reason;
    EXPECT_NEAR(o.energy, 0.5 * k * amplitude * amplitude, 1e-12 * o.energy) << period;
    EXPECT_EQ(o.admissible, period > graze) << period << ": " << o.reason;
    EXPECT_EQ(o.sequence, std::vector<int>{0});
  }
  // The transitions of that family: the lower wall grazed at the closed form's period.
  std::vector<double> periods;
  std::vector<bool> admissible;
  for (double t = 1.7; t <= 2.6; t += 0.01) {
    periods.push_back(t);
    admissible.push_back(OneImpactOrbit(b, t, {}, 0).admissible);
  }
  const std::vector<Transition> transitions = OneImpactTransitions(b, periods, admissible, 0);
  ASSERT_EQ(transitions.size(), 1u);
  EXPECT_EQ(transitions[0].kind, TransitionKind::kGrazing);
  EXPECT_EQ(transitions[0].contact, 1);  // the lower wall, contact 2
  EXPECT_NEAR(transitions[0].period, graze, 1e-10);  // Brent on a smooth g(T): to ~1e-12 of T
  // Sequence (1, 2): the alternating orbit at t2 = T / 2 with the closed form's energy.
  for (double amplitude : {1.6, 2.0, 3.0}) {
    const double period = 2.0 * (M_PI - std::acos(d1 / amplitude) - std::acos(d2 / amplitude)) / w;
    const std::vector<Orbit> orbits = TwoImpactOrbits(b, period, {}, 0, 1);
    const Orbit* alternating = nullptr;
    for (const Orbit& o : orbits) {
      if (std::abs(o.times[0] - 0.5 * period) < 1e-12 * period) alternating = &o;
    }
    ASSERT_NE(alternating, nullptr) << amplitude;
    EXPECT_TRUE(alternating->admissible) << alternating->reason;
    EXPECT_NEAR(alternating->energy, 0.5 * k * amplitude * amplitude, 1e-10 * alternating->energy) << amplitude;
    EXPECT_EQ(alternating->sequence, (std::vector<int>{0, 1}));
  }
}

// Where a family of one contact grazes another (transitions.csv's grazing
// rows with that contact), the family of the two meets it: the graze time t_g
// is a root of the (1, 2) signal and the (1, 2) orbit there is the grazing
// 1-impact orbit (an impact of zero velocity). Unlike one contact's grazing
// (bridge.h) the two NC2 conditions, on two walls, stay independent: no line
// of orbits, no bridge. The (1, 2) branch passes through, its impact
// velocity on wall 2 changing sign: admissible on one side only. (The
// clearance: the paper's chain between x2 <= 1 and x2 >= -1.2.)
TEST(ContactsAnalysis, AnotherContactsGrazingIsAJunctionNotABridge) {
  Model m = PaperModel();
  m.contacts = {DofContact(2, 1, true, 1.0, 1.0), DofContact(2, 1, false, 1.2, 1.0)};
  const AnalysisBasis b(m);
  std::vector<double> periods;
  std::vector<bool> admissible;
  for (double t = 1.0; t <= 10.0; t += 0.01) {
    periods.push_back(t);
    admissible.push_back(OneImpactOrbit(b, t, {}, 0).admissible);
  }
  int junctions = 0;
  for (const Transition& tr : OneImpactTransitions(b, periods, admissible, 0)) {
    if (tr.kind != TransitionKind::kGrazing || tr.contact != 1) continue;
    ++junctions;
    const double tg_period = tr.period;
    const Orbit one = OneImpactOrbit(b, tg_period, {}, 0);
    const SegmentCheck seg = CheckSegment(b, b.contacts[1], one.y0, tg_period);
    const double tg = seg.t_at_max;
    // The graze: wall 2 reached (to the transition's ~1e-15 in T) at rest.
    EXPECT_LT(std::abs(seg.max_excess), 1e-12);
    const std::vector<double> roots = TwoImpactRoots(b, tg_period, {}, 0, 1);
    double nearest = INFINITY;
    for (double r : roots) nearest = std::min(nearest, std::abs(r - tg));
    // Both are roots located to ~1e-15 relative; 1e-9 T leaves room for the
    // graze time's error at a tangency (the square root of 1e-15 ~ 3e-8 in
    // the worst case, measured ~1e-11).
    EXPECT_LT(nearest, 1e-9 * tg_period) << "T_g = " << tg_period;
    const Orbit two = TwoImpactOrbitAt(b, tg, tg_period, {}, 0, 1);
    EXPECT_FALSE(two.degenerate) << "T_g = " << tg_period;
    EXPECT_LT((two.z0 - one.z0).norm(), 1e-9 * one.z0.norm()) << "T_g = " << tg_period;
    // Either side, 1e-3 away: the (1, 2) root near t_g, its velocity on wall
    // 2 just before the impact (> 0 towards it), admissible where it is > 0.
    int sides = 0;
    for (double dt : {-1e-3, 1e-3}) {
      const double period = tg_period + dt;
      double t2 = INFINITY;
      for (double r : TwoImpactRoots(b, period, {}, 0, 1)) {
        if (std::abs(r - tg) < std::abs(t2 - tg)) t2 = r;
      }
      const Orbit o = TwoImpactOrbitAt(b, t2, period, {}, 0, 1);
      Eigen::VectorXd y = o.y0;
      Flow(b, t2, y);
      const double vc = ContactVelocity(b, b.contacts[1], y);
      // n_2 . v = -v2 for the lower wall: moving towards it is > 0.
      EXPECT_GT(std::abs(vc), 1e-5) << "T = " << period;
      EXPECT_EQ(o.admissible, vc > 0.0) << "T = " << period << ": " << o.reason;
      sides += vc > 0.0 ? 1 : -1;
    }
    EXPECT_EQ(sides, 0) << "T_g = " << tg_period << ": the velocity keeps its sign";
  }
  // T_g = 2.9555, 5.8457, 8.3170 (as in the orbits-clearance-1 regression
  // case, on a coarser grid) and 9.1961 (a zone that grid does not resolve).
  EXPECT_EQ(junctions, 4);
}

// The monodromy of a two-contact orbit (each impact with its own contact's
// saltation matrix) against finite differences of the exact simulator: the
// paper's chain with stops x2 <= 1 and x1 >= -0.6 (different dofs: the two
// saltation matrices differ), an admissible (1, 2) orbit from its state z(tau)
// at tau = t2 / 4 (in flight: a perturbed start stays clear of the walls)
// over one period, whose linearisation is S(tau) M S(-tau). Central
// differences with h = 1e-6 of the state: truncation ~h^2 |D^3 phi| ~1e-12,
// round-off ~1e-15 / h = 1e-9, so 1e-6 of |J| leaves room for the flow's
// growth along the orbit.
TEST(ContactsAnalysis, SaltationMultipliersMatchFiniteDifferencesOfTheSimulator) {
  Model m = PaperModel();
  m.contacts = {DofContact(2, 1, true, 1.0, 1.0), DofContact(2, 0, false, 0.6, 1.0)};
  Validate(m);
  const AnalysisBasis b(m);
  std::optional<Orbit> found;
  for (double t = 3.0; t < 12.0 && !found; t += 0.25) {
    for (const Orbit& o : TwoImpactOrbits(b, t, {}, 0, 1)) {
      if (o.admissible && !found) found = o;
    }
  }
  ASSERT_TRUE(found.has_value());
  const Orbit* orbit = &*found;
  const double period = orbit->period;
  const double tau = orbit->times[0] / 4.0;
  const Eigen::MatrixXd jm = FlowMatrix(b, tau) * Monodromy(b, *orbit) * FlowMatrix(b, -tau);
  // Physical <-> modal: z = P y.
  Eigen::MatrixXd p(4, 4);
  for (int i = 0; i < 4; ++i) p.col(i) = PhysicalOf(b, Eigen::VectorXd::Unit(4, i));
  const Eigen::MatrixXd expected = p * jm * p.inverse();
  auto end_state = [&](const Eigen::Vector4d& z0) {
    SimulateOptions opt;
    opt.t_end = period;
    opt.sample_dt = 0.0;
    return nsmodal::Simulate(m, z0.head(2), z0.tail(2), opt).final_state;
  };
  Eigen::VectorXd y_tau = orbit->y0;
  Flow(b, tau, y_tau);
  const Eigen::Vector4d z0 = PhysicalOf(b, y_tau);
  EXPECT_LE((end_state(z0) - z0).norm(), 1e-12 * z0.norm());  // periodic: the orbit and the simulator agree
  Eigen::Matrix4d fd;
  const double h = 1e-6;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector4d dz = h * Eigen::Vector4d::Unit(i);
    fd.col(i) = (end_state(z0 + dz) - end_state(z0 - dz)) / (2.0 * h);
  }
  EXPECT_LE((fd - expected).norm(), 1e-6 * expected.norm()) << "fd\n" << fd << "\nexpected\n" << expected;
  // And the multipliers' verdict is the dense monodromy's.
  const Stability st = OrbitStability(b, *orbit);
  EXPECT_TRUE(st.defined);
}

// Bad input: each names the contact's index and field.
std::string ErrorOf(const std::string& scene) {
  try {
    ParseScene(scene, "test.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Contacts, BadContactsAreRefusedNamingTheContactAndField) {
  const std::string chain = "[system]\nmasses = [1.0, 1.0]\nsprings = [0.85, 2.0]\n";
  const std::string c1 = "[[contact]]\ndof = 2\ngap = 1.0\nrestitution = 1.0\n";
  EXPECT_NE(ErrorOf(chain + c1 + "[[contact]]\nnormal = [0.0, 0.0]\ngap = 1.0\nrestitution = 1.0\n")
                .find("contact[2].normal: is zero"),
            std::string::npos);
  EXPECT_NE(ErrorOf(chain + c1 + "[[contact]]\ndof = 1\ngap = 0.0\nrestitution = 1.0\n").find("contact[2].gap"),
            std::string::npos);
  EXPECT_NE(ErrorOf(chain + c1 + "[[contact]]\ndof = 2\nside = \"lower\"\ngap = -1.0\nrestitution = 1.0\n")
                .find("contact[2].gap: must be positive"),
            std::string::npos);
  EXPECT_NE(ErrorOf(chain + c1 + "[[contact]]\ndof = 2\ngap = 2.0\nrestitution = 1.0\n")
                .find("contact[2].normal: duplicates contact 1"),
            std::string::npos);
  EXPECT_NE(ErrorOf(chain + c1 + "[[contact]]\ndof = 3\ngap = 1.0\nrestitution = 1.0\n").find("contact[2].dof"),
            std::string::npos);
  EXPECT_NE(ErrorOf(chain + c1 + "[[contact]]\nbetween = [1, 1]\ngap = 1.0\nrestitution = 1.0\n")
                .find("contact[2].between"),
            std::string::npos);
  EXPECT_NE(ErrorOf(chain + c1 + "[[contact]]\ndof = 1\ngap = 1.0\nrestitution = 1.5\n")
                .find("contact[2].restitution"),
            std::string::npos);
  EXPECT_NE(ErrorOf(chain + c1 + "[[contact]]\ndof = 1\nside = \"left\"\ngap = 1.0\nrestitution = 1.0\n")
                .find("contact[2].side"),
            std::string::npos);
  EXPECT_NE(ErrorOf(chain + c1 + "[[contact]]\ndof = 1\ngap = 1.0\n").find("contact[2].restitution: is missing"),
            std::string::npos);
  EXPECT_NE(ErrorOf(chain + "gap = 1.0\nrestitution = 1.0\n" + c1).find("contact: give the contacts either"),
            std::string::npos);
  EXPECT_NE(ErrorOf(chain + c1 + "[[contact]]\ndof = 1\ngap = 1.0\nrestitution = 1.0\nheight = 2\n")
                .find("contact[2].height"),
            std::string::npos);
  // Opposing walls that leave no room: the clearance of two faces.
  Model m = Clearance(1.0, 1.0, 1.0, 1.0);
  m.contacts[1].gap = -1.0;
  try {
    Validate(m);
    ADD_FAILURE() << "no room was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("leaves no room between the walls"), std::string::npos) << e.what();
  }
  // A dof contact whose normal says another wall (a hand-made or unpickled state).
  Model mismatch = Clearance(1.0, 1.0, 1.0, 1.0);
  mismatch.contacts[1].normal[0] = 5.0;
  try {
    Validate(mismatch);
    ADD_FAILURE() << "a normal that is not its form's was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("contact[2].normal: does not match"), std::string::npos) << e.what();
  }
  // A start beyond any wall names it.
  try {
    nsmodal::Simulate(Clearance(1.0, 0.5, 1.0, 1.0), Eigen::VectorXd::Constant(1, -0.6), Eigen::VectorXd::Zero(1),
                      SimulateOptions{});
    ADD_FAILURE() << "a start beyond the lower wall was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("contact 2 (x1 >= -0.5)"), std::string::npos) << e.what();
  }
  // The periodic-orbit analysis names the restitution below 1 of the contact that has it.
  try {
    AnalysisBasis b(Clearance(1.0, 1.0, 1.0, 0.5));
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("contact[2].restitution"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nsmodal

namespace nsmodal {
namespace {

// Two contacts held at once with a coupled Delassus matrix, one released
// while the other stays held (issue 24): mass 1 on a spring rests on a stop
// below it (x1 >= -0.5) and mass 2, on a soft spring, rests on mass 1 (the
// relative contact x2 >= x1 - 0.2: n2 = e1 - e2, so G_12 = n1' M^-1 n2 =
// 1/m1 != 0), both pushed down by a constant force. A harmonic force on mass
// 2 lifts it off mass 1 each period while mass 1 stays on its stop: the
// release of contact 2 alone from the held pair {1, 2}. (The release is
// consistent there: with S' = S - {j} held, lambda_j^S = -w_j^S' / s, s > 0
// the Schur complement of G_S, so the force of j falling through 0 is its
// gap's acceleration turning to separation, and the others' forces do not
// jump.) Mass 2 falls back (e = 0.5, a Zeno sequence) and is held again.
// Which contacts at rest stay held is Moreau's acceleration-level law, not a
// decision one at a time: mass 1 against x1 <= 0.5 and mass 2 against mass 1
// (x1 - x2 <= 0.3), unit masses, so G = [1 1; 1 2]. With free normal
// accelerations a = (1, 3) both push in, but holding both would need the
// forces G^-1 a = (-1, 2): contact 1 would pull. Holding contact 1 first,
// contact 2 still pushes in along that motion (3 - 1 = 2 > 0): the rule one
// at a time in that order holds both. The LCP holds contact 2 alone
// (lambda = (0, 1.5), contact 1's acceleration 1.5 - 1 = 0.5 away).
TEST(Contacts, TheContactsAtRestThatStayHeldAreMoreausAccelerationLaw) {
  Model m;
  m.mass = Eigen::Matrix2d::Identity();
  m.stiffness = Eigen::Matrix2d::Identity();
  m.contacts = {DofContact(2, 0, true, 0.5, 0.5), BetweenContact(2, 0, 1, 0.3, 0.5)};
  const Eigen::Vector2d x(0.5, 0.2);
  m.forcing.constant = Eigen::Vector2d(1.0, -2.0) + x;  // M a + K x
  Validate(m);
  const ContactModel cm(m);
  Eigen::VectorXd z(4);
  z << x, 0.0, 0.0;
  EXPECT_NEAR(cm.FreeContactAcceleration(0, 0.0, x, z.tail(2)), 1.0, 1e-15);
  EXPECT_NEAR(cm.FreeContactAcceleration(1, 0.0, x, z.tail(2)), 3.0, 1e-15);
  std::vector<int> held;
  ASSERT_TRUE(cm.HeldByForces({0, 1}, 0.0, z, held));
  EXPECT_EQ(held, std::vector<int>{1});
  // Either contact alone is held (its own acceleration pushes in).
  ASSERT_TRUE(cm.HeldByForces({0}, 0.0, z, held));
  EXPECT_EQ(held, std::vector<int>{0});
  ASSERT_TRUE(cm.HeldByForces({1}, 0.0, z, held));
  EXPECT_EQ(held, std::vector<int>{1});
}

TEST(Contacts, OneOfTwoHeldContactsIsReleasedWithACoupledDelassusMatrix) {
  Model m;
  m.mass = Eigen::Vector2d(1.0, 0.5).asDiagonal();
  m.stiffness = Eigen::Matrix2d::Zero();
  m.stiffness(0, 0) = 1.0;
  m.stiffness(1, 1) = 0.1;
  m.contacts = {DofContact(2, 0, false, 0.5, 0.5), BetweenContact(2, 0, 1, 0.2, 0.5)};
  m.forcing.constant = Eigen::Vector2d(-2.0, -1.0);
  m.forcing.amplitude = Eigen::Vector2d(0.0, 1.5);
  m.forcing.frequency = 2.0;
  Validate(m);
  const ContactModel cm(m);
  ASSERT_GT(std::abs(cm.delassus(0, 1)), 0.5);
  // Both held at rest (x1 = -0.5, x2 = -0.7): with G = [1 -1; -1 3] and the
  // free normal accelerations (1.5, 0.36 - 3 cos 2t), the forces are
  // lambda = G^-1 H a = ((4.86 - 3 cos 2t) / 2, 0.93 - 1.5 cos 2t): contact 1
  // never lets go, contact 2 does where cos 2t > 0.62.
  const double lift = (2.0 * M_PI - std::acos(0.62)) / 2.0;  // its first release after t = 2
  const Eigen::Vector2d x0(-0.5, -0.7), v0(0.0, 0.0);
  std::vector<std::vector<Eigen::VectorXd>> runs;
  for (auto [integrator, step] : {std::pair(Integrator::kExact, 1e-5), std::pair(Integrator::kCvode, 1e-5),
                                  std::pair(Integrator::kMoreauJean, 1e-5)}) {
    SimulateOptions opt;
    opt.integrator = integrator;
    opt.t_end = 20.0;
    opt.sample_dt = 1e-3;
    opt.rtol = 1e-10;
    opt.atol = 1e-12;
    opt.step = step;
    SimulationObserver obs;
    runs.emplace_back();
    obs.on_sample = [&](double, const Eigen::VectorXd& z) { runs.back().push_back(z); };
    const SimulationSummary sum = Simulate(m, x0, v0, opt, obs);
    ASSERT_EQ(sum.status, SimulationStatus::kFinished) << ToString(integrator) << ": " << sum.message;
  }
  const std::vector<Eigen::VectorXd>& exact = runs[0];
  ASSERT_EQ(runs[1].size(), exact.size());
  ASSERT_EQ(runs[2].size(), exact.size());
  double cvode = 0.0, mj = 0.0, off_stop = 0.0, penetration = -1.0;
  std::optional<double> first_lift;
  for (std::size_t i = 0; i < exact.size(); ++i) {
    cvode = std::max(cvode, (runs[1][i].head(2) - exact[i].head(2)).cwiseAbs().maxCoeff());
    mj = std::max(mj, (runs[2][i].head(2) - exact[i].head(2)).cwiseAbs().maxCoeff());
    off_stop = std::max(off_stop, std::abs(exact[i][0] + 0.5));
    penetration = std::max(penetration, exact[i][0] - exact[i][1] - 0.2);
    if (!first_lift && i * 1e-3 > 2.0 && exact[i][1] + 0.7 > 1e-9) first_lift = i * 1e-3;
  }
  // Mass 1 stays on its stop exactly; mass 2 never enters mass 1.
  EXPECT_EQ(off_stop, 0.0);
  EXPECT_LE(penetration, 1e-15);
  // Mass 2 leaves at the closed form's release: x2 + 0.7 grows as
  // (6 |sin 2t*| / 6) (t - t*)^3 = 0.785 (t - t*)^3, 1e-9 after 1.1e-3.
  ASSERT_TRUE(first_lift.has_value());
  EXPECT_GE(*first_lift, lift);
  EXPECT_LE(*first_lift, lift + 2e-3);
  // CVODE (rtol 1e-10) to 1e-8 over 20 s and ~100 impacts (measured 3e-10;
  // before it bounded its steps while held it stepped over every release and
  // kept both held to the end); Moreau-Jean to its first order in h = 1e-5
  // (measured 2.5e-5).
  EXPECT_LT(cvode, 1e-8);
  EXPECT_LT(mj, 1e-4);
  // Without samples (which stop CVODE every 1e-3 here) its steps are bounded
  // by the held bound alone: the same end.
  const Trace unsampled = SimulateTrace(m, x0, v0, Integrator::kCvode, 20.0, 1e-10);
  EXPECT_LT((unsampled.summary.final_state.head(2) - exact.back().head(2)).cwiseAbs().maxCoeff(), 1e-8);
}

}  // namespace
}  // namespace nsmodal
