// The impact damper (issue 24): a primary mass M on a spring k, forced by
// F cos(W t), with a free mass m rattling in a cavity of clearance d (two
// relative contacts, x2 - x1 <= d/2 and x1 - x2 <= d/2, restitution e). Its
// classical steady state (Masri and Caughey 1966): two impacts per forcing
// period, one on each wall, half a period apart, the motion antisymmetric
// (z(t + pi/W) = -z(t)). Derived here from that symmetry alone, as the test's
// independent oracle, and compared with ForcedProblem's general solution
// (the affine fixed point with the rigid-body mode bordered, forced_orbit.h),
// its stability with finite differences of the exact simulator, and the
// orbits with the three integrators over long horizons.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <string>
#include <vector>

#include "nsmodal/error.h"
#include "nsmodal/forced_orbit.h"
#include "nsmodal/modal_basis.h"
#include "nsmodal/model.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/return_map.h"
#include "nsmodal/simulate.h"
#include "nsmodal/stability.h"
#include "nsmodal/two_impact.h"
#include "nsmodal/validate.h"

namespace nsmodal {
namespace {

struct Damper {
  double big_m = 1.0, k = 1.0, m = 0.1, d = 1.0, e = 0.6, f = 0.3;
};

Model DamperModel(const Damper& p, double zeta = 0.0) {
  Model model;
  model.mass = Eigen::Vector2d(p.big_m, p.m).asDiagonal();
  model.stiffness = Eigen::Matrix2d::Zero();
  model.stiffness(0, 0) = p.k;
  if (zeta > 0.0) {
    model.damping = Eigen::Matrix2d::Zero();
    model.damping(0, 0) = 2.0 * zeta * std::sqrt(p.k * p.big_m);
  }
  model.contacts = {BetweenContact(2, 1, 0, 0.5 * p.d, p.e), BetweenContact(2, 0, 1, 0.5 * p.d, p.e)};
  model.forcing.amplitude = Eigen::Vector2d(p.f, 0.0);
  model.forcing.frequency = 1.0;
  Validate(model);
  return model;
}

// The antisymmetric motion with impacts at t = 0 (the free mass y on the
// wall y - x = d/2) and t = h = pi/W (on y - x = -d/2), forcing
// F cos(W t + alpha). With the primary x = A cos(w t) + B sin(w t) + X cos(W t
// + alpha) on (0, h) (w^2 = k/M, X = F / (k - M W^2)), x(0) = x0, x(h) = -x0,
// x'(0+) = u+, x'(h-) = -u- (the antisymmetry), the free mass's flight
// y(h) - y(0) = w+ h = -(2 x0 + d), momentum M (u- - u+) = 2 m w+ (w- = -w+)
// and Newton's law w+ - u+ = -e (w- - u-): seven linear equations in
// (A, B, x0, u+, u-, w+, P = X cos alpha, Q = X sin alpha), and P^2 + Q^2 = X^2.
struct Symmetric {
  double alpha, x0, u_plus, w_plus, u_minus;
};

std::vector<Symmetric> MasriCaughey(const Damper& p, double big_w) {
  const double w = std::sqrt(p.k / p.big_m), h = M_PI / big_w;
  const double amp = p.f / (p.k - p.big_m * big_w * big_w);
  const double c = std::cos(w * h), s = std::sin(w * h);
  Eigen::Matrix<double, 7, 8> l = Eigen::Matrix<double, 7, 8>::Zero();
  Eigen::Matrix<double, 7, 1> r = Eigen::Matrix<double, 7, 1>::Zero();
  // Unknowns: 0 A, 1 B, 2 x0, 3 u+, 4 u-, 5 w+, 6 P, 7 Q.
  l.row(0) << 1, 0, -1, 0, 0, 0, 1, 0;                     // x(0) = x0
  l.row(1) << 0, w, 0, -1, 0, 0, 0, -big_w;                // x'(0+) = u+
  l.row(2) << c, s, 1, 0, 0, 0, -1, 0;                     // x(h) = -x0
  l.row(3) << -w * s, w * c, 0, 0, 1, 0, 0, big_w;         // x'(h-) = -u-
  l.row(4) << 0, 0, 2, 0, 0, h, 0, 0;                      // w+ h = -(2 x0 + d)
  r[4] = -p.d;
  l.row(5) << 0, 0, 0, -p.big_m, p.big_m, -2.0 * p.m, 0, 0;  // momentum
  l.row(6) << 0, 0, 0, -1, -p.e, 1.0 - p.e, 0, 0;          // restitution
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(l);
  EXPECT_EQ(lu.rank(), 7);
  const Eigen::VectorXd base = lu.solve(Eigen::VectorXd(r));
  EXPECT_LT((l * base - r).norm(), 1e-12);
  const Eigen::VectorXd null = lu.kernel().col(0);
  // (P0 + t NP)^2 + (Q0 + t NQ)^2 = X^2.
  const double qa = null[6] * null[6] + null[7] * null[7];
  const double qb = 2.0 * (base[6] * null[6] + base[7] * null[7]);
  const double qc = base[6] * base[6] + base[7] * base[7] - amp * amp;
  const double disc = qb * qb - 4.0 * qa * qc;
  std::vector<Symmetric> out;
  if (disc < 0.0) return out;
  for (double sign : {-1.0, 1.0}) {
    const double t = (-qb + sign * std::sqrt(disc)) / (2.0 * qa);
    const Eigen::VectorXd x = base + t * null;
    double alpha = std::atan2(x[7] / amp, x[6] / amp);
    if (alpha < 0.0) alpha += 2.0 * M_PI;
    out.push_back({alpha, x[2], x[3], x[5], x[4]});
  }
  return out;
}

// The (1, 2) orbits ForcedProblem finds with equal flights (t2 - t1 = P/2).
std::vector<ForcedOrbit> SymmetricOrbits(const ForcedProblem& problem) {
  std::vector<ForcedOrbit> out;
  for (const Eigen::VectorXd& u : problem.FindAll()) {
    if (std::abs(u[1] - 0.5 * problem.period()) <= 1e-9 * problem.period()) out.push_back(problem.Orbit(u));
  }
  return out;
}

// Each closed-form solution is one of ForcedProblem's, and each symmetric
// solution of ForcedProblem one of the closed form's: the phase, the state
// after the first impact and the free mass's velocity. Tolerance: both are
// solved to round-off (Newton to 1e-13 of d, the closed form by LU); 1e-9
// leaves the Jacobians' conditioning (~1e3) three orders of room.
TEST(ImpactDamper, TheSymmetricResponseIsMasriAndCaugheysClosedForm) {
  const Damper p;
  const Model model = DamperModel(p);
  int compared = 0;
  for (double big_w : {0.6, 0.8, 1.2, 1.5, 2.0}) {
    const std::vector<Symmetric> closed = MasriCaughey(p, big_w);
    const ForcedProblem problem(model, std::vector<int>{0, 1}, 1, big_w, p.f);
    const std::vector<ForcedOrbit> found = SymmetricOrbits(problem);
    ASSERT_EQ(found.size(), closed.size()) << "W = " << big_w;
    for (const Symmetric& s : closed) {
      const ForcedOrbit* match = nullptr;
      for (const ForcedOrbit& o : found) {
        if (std::abs(std::remainder(o.u[0] - s.alpha, 2.0 * M_PI)) < 1e-6) match = &o;
      }
      ASSERT_NE(match, nullptr) << "W = " << big_w << ": no orbit at alpha = " << s.alpha;
      const Eigen::VectorXd& z = match->after[0];
      EXPECT_NEAR(std::remainder(match->u[0] - s.alpha, 2.0 * M_PI), 0.0, 1e-9);
      EXPECT_NEAR(z[0], s.x0, 1e-9);
      EXPECT_NEAR(z[1], s.x0 + 0.5 * p.d, 1e-9);  // on the wall y - x = d/2
      EXPECT_NEAR(z[2], s.u_plus, 1e-9);
      EXPECT_NEAR(z[3], s.w_plus, 1e-9);
      EXPECT_NEAR(match->before[0][2], s.u_minus, 1e-9);
      // The second impact: the antisymmetric image.
      EXPECT_NEAR(match->after[1][0], -s.x0, 1e-9);
      EXPECT_NEAR(match->after[1][3], -s.w_plus, 1e-9);
      ++compared;
    }
  }
  EXPECT_GE(compared, 6);
}

// The multipliers of the admissible symmetric orbits (with each wall's saltation matrix
// and the free mass's drift) against central differences of the exact
// simulator over one period from t = 0: the monodromy there is similar to
// the one after the first impact, so the eigenvalues agree. Step 1e-6 of the
// state: truncation ~1e-12, round-off ~1e-16/1e-6 = 1e-10 of |J|; 1e-6 of
// max(1, |lambda|) covers the eigenvalues' conditioning.
TEST(ImpactDamper, ItsStabilityMatchesFiniteDifferencesOfTheSimulator) {
  const Damper p;
  const Model model = DamperModel(p);
  int stable = 0, unstable = 0;
  for (double big_w : {0.8, 1.2, 1.5}) {
    const ForcedProblem problem(model, std::vector<int>{0, 1}, 1, big_w, p.f);
    for (const ForcedOrbit& o : SymmetricOrbits(problem)) {
      if (!o.admissible) continue;  // (beyond a wall: no motion to differentiate)
      const Eigen::VectorXd z0 = problem.StateAt(o, 0.0);
      SimulateOptions opt;
      opt.integrator = Integrator::kExact;
      opt.t_end = o.period;
      opt.sample_dt = o.period;
      auto end = [&](const Eigen::VectorXd& z) {
        return Simulate(problem.model(), z.head(2), z.tail(2), opt).final_state;
      };
      Eigen::Matrix4d j;
      for (int k = 0; k < 4; ++k) {
        const double step = 1e-6 * std::max(1.0, std::abs(z0[k]));
        Eigen::VectorXd a = z0, b = z0;
        a[k] += step;
        b[k] -= step;
        j.col(k) = (end(a) - end(b)) / (2.0 * step);
      }
      Eigen::VectorXcd fd = Eigen::EigenSolver<Eigen::Matrix4d>(j, false).eigenvalues();
      Eigen::VectorXcd mu = o.multipliers;
      auto by_modulus = [](Eigen::VectorXcd v) {
        std::vector<std::complex<double>> s(v.data(), v.data() + v.size());
        std::sort(s.begin(), s.end(), [](auto x, auto y) {
          return std::abs(x) != std::abs(y) ? std::abs(x) < std::abs(y) : x.imag() < y.imag();
        });
        return s;
      };
      const auto a = by_modulus(fd), b = by_modulus(mu);
      ASSERT_EQ(a.size(), b.size());
      const double scale = std::max(1.0, std::abs(b.back()));
      for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_LT(std::abs(a[i] - b[i]), 1e-6 * scale) << "W = " << big_w << ": " << a[i] << " vs " << b[i];
      }
      (o.stable ? stable : unstable) += 1;
    }
  }
  // Both kinds occur on these frequencies, so the comparison covers both.
  EXPECT_GT(stable, 0);
  EXPECT_GT(unstable, 0);
}

// The admissible symmetric orbits simulated 200 periods by each integrator
// agree with their prediction (validate's verdicts: a stable orbit stays,
// an unstable one departs at its multipliers' rate).
TEST(ImpactDamper, TheThreeIntegratorsFollowTheOrbitsOverLongHorizons) {
  const Damper p;
  const Model model = DamperModel(p);
  ValidateOptions options;
  options.periods = 200;
  int admissible = 0;
  for (double big_w : {0.8, 1.2, 1.5}) {
    const ForcedProblem problem(model, std::vector<int>{0, 1}, 1, big_w, p.f);
    for (const ForcedOrbit& o : SymmetricOrbits(problem)) {
      if (!o.admissible) continue;
      ++admissible;
      for (Integrator integrator : {Integrator::kExact, Integrator::kCvode, Integrator::kMoreauJean}) {
        const ForcedOrbitValidation v = ValidateForcedOrbit(model, o, integrator, options);
        EXPECT_TRUE(v.consistent) << "W = " << big_w << ", " << ToString(integrator) << ": " << v.reason;
      }
    }
  }
  EXPECT_GE(admissible, 2);
}

// A free mass that no contact struck moves leaves its position undetermined:
// refused naming the sequence.
TEST(ImpactDamper, ASequenceThatDoesNotStopTheFreeMassIsRefused) {
  const Damper p;
  Model model = DamperModel(p);
  model.contacts.push_back(DofContact(2, 0, true, 2.0, 0.6));  // the primary's stop
  Validate(model);
  try {
    ForcedProblem problem(model, std::vector<int>{2}, 1, 1.2, p.f);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sequence: "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("rigid-body mode"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(ForcedProblem(model, std::vector<int>{0, 1}, 1, 1.2, p.f));
}

}  // namespace
}  // namespace nsmodal

namespace nsmodal {
namespace {

// A sequence a rotation maps onto itself, (1, 2, 1, 2) over two forcing
// periods: every orbit FindAll returns (canonical: started at the impact
// earliest in the forcing cycle, the free mass's shift moved with it) solves
// the problem to Newton's tolerance (1e-13 of the gap; 1e-11 leaves the
// rotation's round-off room).
TEST(ImpactDamper, ARotatedStartKeepsTheFreeMassWhereItIs) {
  const Damper p;
  const Model model = DamperModel(p);
  for (double big_w : {0.8, 1.2}) {
    const ForcedProblem problem(model, std::vector<int>{0, 1, 0, 1}, 2, big_w, p.f);
    const std::vector<Eigen::VectorXd> found = problem.FindAll();
    EXPECT_FALSE(found.empty());
    for (const Eigen::VectorXd& u : found) {
      Eigen::VectorXd r;
      ASSERT_TRUE(problem.Residual(u, r));
      EXPECT_LT(r.cwiseAbs().maxCoeff(), 1e-11 * problem.gap_scale()) << "W = " << big_w;
    }
  }
}

}  // namespace
}  // namespace nsmodal

namespace nsmodal {
namespace {

// The free mass chatters onto one wall and rides it (held), the cavity's
// other wall then at a constant distance with zero relative velocity: CVODE
// must not take that identically zero velocity for a root (it stopped with
// "root found at and very near t" before), and agrees with the exact
// integrator on the time held (measured 1.65743 against 1.65732: 1e-3 covers
// the Zeno truncations' different ends).
TEST(ImpactDamper, CvodeRidesOneWallOfTheCavity) {
  const Damper p;
  Model model = DamperModel(p, 0.02);
  model.forcing.frequency = 0.9733;
  SimulateOptions opt;
  opt.t_end = 12.0;
  opt.sample_dt = 0.1;  // (CVODE restarts at the samples too: the case that stopped it)
  SimulationObserver samples;
  samples.on_sample = [](double, const Eigen::VectorXd&) {};
  const Eigen::Vector2d x0(-2.2777596298860705, -2.1933021984407439), v0(4.2916053356291624, 3.2513213702650132);
  const SimulationSummary exact = Simulate(model, x0, v0, opt, samples);
  opt.integrator = Integrator::kCvode;
  const SimulationSummary cvode = Simulate(model, x0, v0, opt, samples);
  ASSERT_EQ(cvode.status, SimulationStatus::kFinished) << cvode.message;
  EXPECT_GT(exact.sticking_time, 1.0);
  EXPECT_NEAR(cvode.sticking_time, exact.sticking_time, 1e-3);
}

}  // namespace
}  // namespace nsmodal

// The conservative impact damper's nonsmooth modes (e = 1, no damping, no
// force): its (1, 2) orbits, a free mass that no spring holds (two_impact.h,
// rigid-body modes).

namespace nsmodal {
namespace {

Model FreeDamper(const Damper& p) {
  Model model = DamperModel(p);
  model.forcing = Forcing{};
  for (Contact& c : model.contacts) c.restitution = 1.0;
  return model;
}

// The non-impacting response of a damper whose free mass is off-centre in
// its cavity (x2 - x1 in [-0.7, 0.3]): the free mass is at rest anywhere, so
// the response is admissible while the primary's amplitude A is at most half
// the clearance, 0.5, with the free mass at c = -0.2 (the cavity's middle),
// not only while A <= 0.3 (the free mass at 0).
TEST(ImpactDamper, ItsLinearResponseCentresTheFreeMassInTheCavity) {
  Damper p;
  Model model = DamperModel(p, 0.02);
  model.contacts = {BetweenContact(2, 1, 0, 0.3, p.e), BetweenContact(2, 0, 1, 0.7, p.e)};
  Validate(model);
  const double w = 0.7;
  const ForcedOrbit unit = LinearResponse(model, w, 1.0);
  const double a_unit = unit.max_interior_gap + 0.5;  // the amplitude per unit force: excess A - 0.5
  ASSERT_GT(a_unit, 0.0);
  for (double a : {0.25, 0.45, 0.55}) {
    const ForcedOrbit o = LinearResponse(model, w, a / a_unit);
    // Linear in the force: A = a; the excess is A minus half the clearance.
    EXPECT_NEAR(o.max_interior_gap, a - 0.5, 1e-12) << "A = " << a;
    EXPECT_EQ(o.admissible, a <= 0.5) << "A = " << a;
    // The free mass in the middle of the cavity.
    EXPECT_NEAR(o.after[0][1], -0.2, 1e-12) << "A = " << a;
  }
  // Simulated from its state at t = 0 (the primary's X = f / (k - M w^2 +
  // i c w), the free mass at rest at c), the admissible one never touches a
  // wall.
  const double f = 0.45 / a_unit;
  const std::complex<double> x1 = f / std::complex<double>(p.k - p.big_m * w * w, 2.0 * 0.02 * std::sqrt(p.k * p.big_m) * w);
  EXPECT_NEAR(std::abs(x1), 0.45, 1e-12);
  Model forced = model;  // the force of that level (LinearResponse's amplitude: the largest |f_i|)
  forced.forcing.amplitude = Eigen::Vector2d(f, 0.0);
  forced.forcing.frequency = w;
  SimulateOptions opt;
  opt.t_end = 20.0 * 2.0 * M_PI / w;
  opt.sample_dt = 0.0;
  const SimulationSummary sum =
      Simulate(forced, Eigen::Vector2d(x1.real(), -0.2), Eigen::Vector2d(-w * x1.imag(), 0.0), opt);
  EXPECT_EQ(sum.impacts, 0);
}

// The symmetric free orbit (impacts at 0 on y - x = d/2 and at T/2 on
// x - y = d/2, z(t + T/2) = -z(t)): with w^2 = k/M, h = w T/2, the primary
// x = x0 cos(w t) + (u0/w) sin(w t) on (0, T/2) and the free mass
// y = x0 + d/2 - V t. x(T/2) = -x0 gives u0 = -w x0 cot(h/2); y(T/2) =
// -(x0 + d/2) gives V = 4 (x0 + d/2) / T; the momentum of the impact at
// T/2, M (u- - u+) = m (w+ - w-), with u- = u0 (Newton's law then holds by
// itself), gives M u0 = m V. So
//   x0 = -4 m (d/2) / (T M w cot(h/2) + 4 m).
TEST(ImpactDamper, ItsFreeSymmetricOrbitsAreTheClosedForm) {
  const Damper p;
  const AnalysisBasis b(FreeDamper(p));
  ASSERT_EQ(b.rigid, 1);
  const double w = std::sqrt(p.k / p.big_m);
  int admissible = 0;
  for (double period = 2.0; period <= 30.0; period += 0.7) {
    const std::vector<double> roots = TwoImpactRoots(b, period, {}, 0, 1);
    ASSERT_TRUE(std::find(roots.begin(), roots.end(), 0.5 * period) != roots.end()) << "T = " << period;
    const Orbit o = TwoImpactOrbitAt(b, 0.5 * period, period, {}, 0, 1);
    const double x0 = -4.0 * p.m * 0.5 * p.d / (period * p.big_m * w / std::tan(0.25 * w * period) + 4.0 * p.m);
    const double u0 = -w * x0 / std::tan(0.25 * w * period), v = 4.0 * (x0 + 0.5 * p.d) / period;
    const Eigen::Vector4d closed(x0, x0 + 0.5 * p.d, u0, -v);
    // Both are O(1) linear algebra on O(1) numbers away from cot(h/2) = 0 or
    // a zero denominator (none on this grid): round-off, 1e-12 with room.
    EXPECT_LT((o.z0 - closed).cwiseAbs().maxCoeff(), 1e-12) << "T = " << period << ": " << o.z0.transpose();
    EXPECT_TRUE(o.potential) << o.reason;
    EXPECT_LT(o.periodicity_residual, 1e-13);
    const double energy = 0.5 * p.big_m * (w * w * x0 * x0 + u0 * u0) + 0.5 * p.m * v * v;
    EXPECT_NEAR(o.energy, energy, 1e-13 * energy);
    admissible += o.admissible;
  }
  EXPECT_GT(admissible, 10);
}

// A primary of two masses (1 and 2 kg on springs 1 and 3 N/m, coupled by
// 0.5 N/m) with the free mass (0.1 kg) between mass 1 (x3 - x1 <= 0.5) and
// mass 2 (x2 - x3 <= 0.3): the two walls' rigid parts differ in size
// (kappa = -|p2_r| / |p1_r| != -1) and the elastic part has two modes.
Model TwoPrimaryDamper() {
  Model model;
  model.mass = Eigen::Vector3d(1.0, 2.0, 0.1).asDiagonal();
  model.stiffness = Eigen::Matrix3d::Zero();
  model.stiffness.topLeftCorner(2, 2) << 1.5, -0.5, -0.5, 3.5;
  model.contacts = {BetweenContact(3, 2, 0, 0.5, 1.0), BetweenContact(3, 1, 2, 0.3, 1.0)};
  Validate(model);
  return model;
}

// Every root t2 of the rigid NC1 signal is a kernel of A_2 one larger than
// the shift's (the second smallest singular value vanishes there), every
// sign change of the signal on a dense grid brackets a root found (none
// missed), and each root's orbit is potential. On the damper the asymmetric
// orbits come in pairs t2, T - t2; on the two-primary damper (|kappa| != 1)
// the exact simulator follows each admissible orbit over a period.
TEST(ImpactDamper, EachRootOfItsSignalIsAKernelOfA2AndNoneIsMissed) {
  const Damper p;
  for (const Model& model : {FreeDamper(p), TwoPrimaryDamper()}) {
    const AnalysisBasis b(model);
    const bool symmetric = model.dofs() == 2;
    int asymmetric = 0, simulated = 0;
    for (double period = 2.0; period <= 40.0; period += 0.37) {
      const std::vector<double> roots = TwoImpactRoots(b, period, {}, 0, 1);
      const SinusoidSum f = TwoImpactSignal(b, period, 0, 1);
      const int grid = 20000;
      for (int i = 0; i < grid; ++i) {
        const double lo = period * i / grid, hi = period * (i + 1) / grid;
        if ((f.Position(lo) < 0.0) == (f.Position(hi) < 0.0)) continue;
        // (T/2, exact, can sit an ulp outside a cell edge i T / grid.)
        const bool found = std::any_of(roots.begin(), roots.end(),
                                       [&](double r) { return r >= lo - 1e-12 * period && r <= hi + 1e-12 * period; });
        EXPECT_TRUE(found) << "T = " << period << ": a sign change in [" << lo << ", " << hi << "] with no root";
      }
      for (double t2 : roots) {
        const Eigen::VectorXd sv =
            Eigen::JacobiSVD<Eigen::MatrixXd>(MatrixA(b, {t2}, period, {0, 1})).singularValues();
        const int n = static_cast<int>(sv.size());
        // Ascending from the back: sv[n-1] the shift (0 in exact
        // arithmetic), sv[n-2] NC1's; A is O(1), so round-off is ~1e-15.
        EXPECT_LT(sv[n - 2], 1e-12) << "T = " << period << ", t2 = " << t2;
        EXPECT_GT(sv[n - 3], 1e-6) << "T = " << period << ", t2 = " << t2;
        asymmetric += std::abs(t2 - 0.5 * period) > 1e-9 * period;
        if (symmetric) {
          const bool mirrored = std::any_of(roots.begin(), roots.end(),
                                            [&](double s) { return std::abs(s - (period - t2)) < 1e-9 * period; });
          EXPECT_TRUE(mirrored) << "T = " << period << ", t2 = " << t2;
        }
        const Orbit o = TwoImpactOrbitAt(b, t2, period, {}, 0, 1);
        EXPECT_TRUE(o.potential) << "T = " << period << ", t2 = " << t2 << ": " << o.reason;
        if (!symmetric && o.admissible && simulated < 20) {
          ++simulated;
          // The exact integrator (contact tolerance 1e-14 of the scale) from
          // the orbit's start to mid-flight, t2 / 2, and on one period more:
          // the same state to 1e-9 of |z0| (an unstable orbit grows the
          // impact times' round-off by its multipliers within the period).
          // (Mid-flight: the period's end is an impact.)
          SimulateOptions opt;
          opt.sample_dt = 0.0;
          opt.t_end = 0.5 * t2;
          const Eigen::VectorXd a = Simulate(model, o.z0.head(3), o.z0.tail(3), opt).final_state;
          opt.t_end = 0.5 * t2 + period;
          const Eigen::VectorXd z = Simulate(model, o.z0.head(3), o.z0.tail(3), opt).final_state;
          EXPECT_LT((z - a).norm(), 1e-9 * o.z0.norm()) << "T = " << period << ", t2 = " << t2;
        }
      }
    }
    EXPECT_GT(asymmetric, 0) << model.dofs() << " dofs";
    if (!symmetric) {
      EXPECT_GT(simulated, 5);
    }
  }
}

// The multipliers (saltation matrices with the free drift, the trivial pair
// taken out along the energy's gradient) against central differences of the
// exact simulator's period map: the trivial pair is a Jordan block that
// differences split by ~sqrt(their error), so the comparison is on the
// similarity invariants tr(J) and tr(J^2), which are not split.
TEST(ImpactDamper, ItsFreeMultipliersMatchFiniteDifferencesOfTheSimulator) {
  const Damper p;
  const Model model = FreeDamper(p);
  const AnalysisBasis b(model);
  int stable = 0, unstable = 0;
  for (double period : {4.0, 6.0, 9.0, 12.0, 13.0}) {
    for (double t2 : TwoImpactRoots(b, period, {}, 0, 1)) {
      const Orbit o = TwoImpactOrbitAt(b, t2, period, {}, 0, 1);
      if (!o.admissible) continue;
      const Stability st = OrbitStability(b, o);
      ASSERT_TRUE(st.defined);
      SimulateOptions opt;
      opt.integrator = Integrator::kExact;
      opt.t_end = period;
      opt.sample_dt = period;
      auto end = [&](const Eigen::VectorXd& z) { return Simulate(model, z.head(2), z.tail(2), opt).final_state; };
      // From mid-flight (the state after the impact sits on a wall, where
      // half the differences would start beyond it): the period map from
      // any point of the orbit has the same multipliers.
      opt.t_end = 0.5 * t2;
      const Eigen::VectorXd mid = end(o.z0);
      opt.t_end = period;
      Eigen::Matrix4d j;
      for (int k = 0; k < 4; ++k) {
        const double step = 1e-6 * std::max(1.0, std::abs(mid[k]));
        Eigen::VectorXd a = mid, c = mid;
        a[k] += step;
        c[k] -= step;
        j.col(k) = (end(a) - end(c)) / (2.0 * step);
      }
      std::complex<double> tr1 = 0.0, tr2 = 0.0;
      for (const std::complex<double>& mu : st.multipliers) {
        tr1 += mu;
        tr2 += mu * mu;
      }
      // Central differences of a map with |J| up to ~100 here: truncation
      // O(step^2 |J'''|) and the simulator's round-off over 2 step: 1e-6 of
      // the scale (as for the forced orbits above).
      const double scale = std::max(1.0, st.max_modulus * st.max_modulus);
      EXPECT_LT(std::abs(tr1 - j.trace()), 1e-6 * scale) << "T = " << period << ", t2 = " << t2;
      EXPECT_LT(std::abs(tr2 - (j * j).trace()), 1e-6 * scale) << "T = " << period << ", t2 = " << t2;
      (st.stable ? stable : unstable) += 1;
    }
  }
  EXPECT_GT(stable, 0);
  EXPECT_GT(unstable, 0);
}

// Simulated 200 periods by each integrator, each admissible orbit does what
// its multipliers say (validate's verdicts).
TEST(ImpactDamper, TheThreeIntegratorsFollowItsFreeOrbits) {
  const Damper p;
  const Model model = FreeDamper(p);
  const AnalysisBasis b(model);
  ValidateOptions options;
  options.periods = 200;
  int admissible = 0;
  for (double period : {4.0, 9.0, 16.0}) {
    for (const Orbit& o : TwoImpactOrbits(b, period, {}, 0, 1)) {
      if (!o.admissible) continue;
      ++admissible;
      for (Integrator integrator : {Integrator::kExact, Integrator::kCvode, Integrator::kMoreauJean}) {
        const OrbitValidation v = ValidateOrbit(model, o, integrator, options);
        EXPECT_TRUE(v.consistent) << "T = " << period << ", " << ToString(integrator) << ": " << v.reason;
      }
    }
  }
  EXPECT_GE(admissible, 3);
}

// What the rigid-body mode leaves undefined is refused, naming the field.
TEST(ImpactDamper, ItsFreeAnalysisRefusesWhatHasNoOrbit) {
  const Damper p;
  Model model = FreeDamper(p);
  const AnalysisBasis b(model);
  auto message = [](const std::function<void()>& f) {
    try {
      f();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message([&] { OneImpactOrbit(b, 5.0); }).find("system.stiffness_matrix: "), std::string::npos);
  EXPECT_NE(message([&] { TwoImpactRoots(b, 5.0, {}, 0, 0); }).find("sequence: contacts 1 and 1: "), std::string::npos);
  // A stop of the primary alone does not move the free mass.
  model.contacts.push_back(DofContact(2, 0, true, 2.0, 1.0));
  const AnalysisBasis with_stop(model);
  const std::string err = message([&] { TwoImpactRoots(with_stop, 5.0, {}, 0, 2); });
  EXPECT_NE(err.find("sequence: contacts 1 and 3: contact 3 does not move the rigid-body mode"), std::string::npos)
      << err;
  // One contact and a free mass: no orbit at all.
  model.contacts = {model.contacts.front()};
  EXPECT_NE(message([&] { AnalysisBasis one(model); }).find("system.stiffness_matrix: "), std::string::npos);
}

}  // namespace
}  // namespace nsmodal
