// Modal truncation (truncation.h): the reduced model is the full one when
// every mode is kept, the residual flexibility is the static one minus the
// kept share, the bound holds on motions of the full model, and truncated
// analyses converge to the full one as modes are added.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "nsmodal/error.h"
#include "nsmodal/flow.h"
#include "nsmodal/modal_basis.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/simulate.h"
#include "nsmodal/trajectory.h"
#include "nsmodal/truncation.h"

namespace nsmodal {
namespace {

// A chain of n unit masses and unit springs, grounded at the first, the
// contact on the last, d = 1.
Model Chain(int n, double e = 1.0) {
  return MakeChain(std::vector<double>(n, 1.0), std::vector<double>(n, 1.0), n - 1, 1.0, e);
}

TEST(Truncation, EveryModeKeptIsTheFullModel) {
  const Model full = Chain(6, 0.9);
  const ModalTruncation t = TruncateModes(full, 6);
  // The same frequencies (an orthogonal change of coordinates; round-off).
  const ModalBasis bf = MakeModalBasis(full), bt = MakeModalBasis(t.model);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(bt.omega[i], bf.omega[i], 1e-13 * bf.omega[5]) << i;
  // x_c is the reduced model's dof 0, and the maps invert each other.
  Eigen::VectorXd x0 = Eigen::VectorXd::LinSpaced(6, 0.2, 0.9), v0 = Eigen::VectorXd::Constant(6, 1.0);
  const Eigen::VectorXd p0 = t.from_physical * x0, w0 = t.from_physical * v0;
  EXPECT_NEAR(p0[0], x0[5], 1e-14);
  EXPECT_LT((t.to_physical * p0 - x0).norm(), 1e-13);
  // The same motion: 20 impacts and more, the same final state. The two runs
  // differ in round-off only, which the impacts amplify (measured ~1e-12).
  SimulateOptions opt;
  opt.t_end = 200.0;
  opt.sample_dt = 0.0;
  const SimulationSummary a = Simulate(full, x0, v0, opt), b = Simulate(t.model, p0, w0, opt);
  ASSERT_EQ(a.status, SimulationStatus::kFinished);
  EXPECT_GE(a.impacts, 20);
  EXPECT_EQ(a.impacts, b.impacts);
  EXPECT_LT((t.to_physical * b.final_state.head(6) - a.final_state.head(6)).norm(), 1e-9);
  EXPECT_LT((t.to_physical * b.final_state.tail(6) - a.final_state.tail(6)).norm(), 1e-9);
  EXPECT_NEAR(b.final_energy, a.final_energy, 1e-12 * a.initial_energy);
}

TEST(Truncation, ResidualFlexibilityIsTheStaticOneMinusTheKeptShare) {
  // f_res = sum over neglected r_i^2 / w_i^2 = (K^-1)_cc - kept share: sums
  // of positive terms, so relative round-off ~N eps.
  const Model full = Chain(50);
  const ModalBasis b = MakeModalBasis(full);
  const double static_flexibility = full.stiffness.llt().solve(Eigen::VectorXd::Unit(50, 49))[49];
  for (int k : {1, 5, 20, 49, 50}) {
    double kept = 0.0;
    for (int i = 0; i < k; ++i) kept += b.r[i] * b.r[i] / (b.omega[i] * b.omega[i]);
    const ModalTruncation t = TruncateModes(full, k);
    EXPECT_NEAR(t.residual_flexibility, static_flexibility - kept, 1e-12 * static_flexibility) << k;
    EXPECT_EQ(t.kept, k);
  }
  EXPECT_EQ(TruncateModes(full, 50).residual_flexibility, 0.0);
}

// max over samples of |x_c carried by modes k..N-1| for a trajectory of
// physical states (rows t, x, v).
double NeglectedShare(const ModalBasis& b, const Eigen::MatrixXd& tr, int k) {
  double worst = 0.0;
  for (long row = 0; row < tr.rows(); ++row) {
    const Eigen::VectorXd q = b.phi_inv * tr.row(row).segment(1, b.n).transpose();
    worst = std::max(worst, std::abs(b.r.tail(b.n - k).dot(q.tail(b.n - k))));
  }
  return worst;
}

TEST(Truncation, TheBoundHoldsOnTheFullModelsOrbitsAndMotions) {
  const Model full = Chain(20);
  const AnalysisBasis ab(full);
  const ModalBasis& b = ab;
  // A 1-ipp orbit of the full chain (T = 8.5, between linear periods).
  const Orbit o = OneImpactOrbit(ab, 8.5);
  ASSERT_TRUE(o.potential);
  const Eigen::MatrixXd tr = OrbitTrajectory(ab, o, 400);
  double tightest = 0.0;
  for (int k = 1; k < 20; ++k) {
    const double bound = TruncateModes(full, k).ContactBound(o.energy);
    const double share = NeglectedShare(b, tr, k);
    // Rigorous (Cauchy-Schwarz); 1e-12 of d for the round-off of the sums.
    EXPECT_LE(share, bound + 1e-12) << k;
    tightest = std::max(tightest, share / bound);
  }
  EXPECT_GT(tightest, 0.05);  // not vacuous: it measures what it bounds
  // A simulated motion with e = 0.9: E <= E0 all along, so the bound at E0.
  Model lossy = full;
  lossy.FirstContact().restitution = 0.9;
  Eigen::VectorXd x0 = Eigen::VectorXd::LinSpaced(20, 0.05, 0.9), v0 = Eigen::VectorXd::Constant(20, 1.0);
  SimulateOptions opt;
  opt.t_end = 100.0;
  opt.sample_dt = 0.01;
  Eigen::MatrixXd samples(10001, 41);
  long rows = 0;
  SimulationObserver obs;
  obs.on_sample = [&](double t, const Eigen::VectorXd& z) {
    if (rows < samples.rows()) {
      samples(rows, 0) = t;
      samples.row(rows).tail(40) = z.transpose();
      ++rows;
    }
  };
  const SimulationSummary s = Simulate(lossy, x0, v0, opt, obs);
  ASSERT_GE(s.impacts, 5);
  for (int k : {1, 3, 10}) {
    EXPECT_LE(NeglectedShare(b, samples.topRows(rows), k), TruncateModes(full, k).ContactBound(s.initial_energy) + 1e-12)
        << k;
  }
}

TEST(Truncation, TruncatedOneImpactOrbitsConvergeToTheFullOne) {
  // The 1-ipp orbit of period 8.5 of a 30-mass chain computed on its first
  // k modes: its energy approaches the full orbit's as k grows, and equals it
  // (round-off) with every mode.
  const Model full = Chain(30);
  const double e_full = OneImpactOrbit(AnalysisBasis(full), 8.5).energy;
  double previous = INFINITY;
  for (int k : {4, 8, 16, 30}) {
    const double e = OneImpactOrbit(AnalysisBasis(TruncateModes(full, k).model), 8.5).energy;
    const double err = std::abs(e - e_full) / e_full;
    EXPECT_LT(err, previous) << k;
    previous = err;
  }
  EXPECT_LT(previous, 1e-12);
}

TEST(Truncation, ModesForABoundAreTheFewestThatMeetIt) {
  const Model full = Chain(40);
  const double energy = 2.0, tol = 1e-3;
  const int k = ModesForContactBound(full, energy, tol);
  EXPECT_LE(TruncateModes(full, k).ContactBound(energy), tol);
  EXPECT_GT(TruncateModes(full, k - 1).ContactBound(energy), tol);
}

TEST(Truncation, BadRequestsNameTheFieldAndValue) {
  const Model full = Chain(5);
  for (int modes : {0, -1, 6}) {
    try {
      TruncateModes(full, modes, "simulate.modes");
      ADD_FAILURE() << modes;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "simulate.modes");
      EXPECT_NE(std::string(e.what()).find(std::to_string(modes) + " modes"), std::string::npos) << e.what();
    }
  }
  for (double tol : {0.0, -1.0, std::nan("")}) {
    EXPECT_THROW(ModesForContactBound(full, 1.0, tol), InputError) << tol;
  }
  EXPECT_THROW(ModesForContactBound(full, -1.0, 1e-3), InputError);
  // The contact on a mass tied to nothing but ground, with the slowest mode
  // elsewhere: the first mode does not move it.
  Model split = MakeChain({1.0, 1.0, 1.0}, {1.0, 1.0, 0.0}, 2, 1.0, 1.0);
  split.stiffness(2, 2) = 10.0;  // mass 3 alone on a stiff ground spring
  EXPECT_THROW(TruncateModes(split, 1), InputError);
  EXPECT_NO_THROW(TruncateModes(split, 3));
  // A free-free chain: the rigid-body mode and an elastic one at least.
  const Model free = MakeChain({1.0, 1.0, 1.0}, {0.0, 1.0, 1.0}, 2, 1.0, 1.0);
  EXPECT_THROW(TruncateModes(free, 1), InputError);
  EXPECT_EQ(TruncateModes(free, 2).model.dofs(), 2);
}

}  // namespace
}  // namespace nsmodal
