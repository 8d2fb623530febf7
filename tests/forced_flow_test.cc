// The damped, forced flight (forced_flow.h), the damping forms and the
// scene keys of damping and forcing, against independent evaluations.
#include <gtest/gtest.h>

#include <complex>

#include "nsmodal/error.h"
#include "nsmodal/forced_flow.h"
#include "nsmodal/modal_basis.h"
#include "nsmodal/model.h"
#include "nsmodal/scene.h"
#include "forced_fixtures.h"
#include "scene_errors.h"

namespace nsmodal {
namespace {

using testing::DampedForcedPaper;
using testing::ReceptanceState;
using Complex = std::complex<double>;

// e^{A t} by scaling and squaring a 30-term Taylor series: independent of the
// eigen-decomposition ForcedFlow uses. |A t| / 2^k <= 1/2 makes the series
// exact to round-off; k squarings add ~k ulps.
Eigen::MatrixXd Expm(const Eigen::MatrixXd& a, double t) {
  const double norm = (a * t).cwiseAbs().rowwise().sum().maxCoeff();
  int k = 0;
  while (norm / std::ldexp(1.0, k) > 0.5) ++k;
  const Eigen::MatrixXd b = a * (t / std::ldexp(1.0, k));
  Eigen::MatrixXd term = Eigen::MatrixXd::Identity(a.rows(), a.cols()), sum = term;
  for (int i = 1; i <= 30; ++i) {
    term = term * b / i;
    sum += term;
  }
  for (int i = 0; i < k; ++i) sum = sum * sum;
  return sum;
}

Eigen::MatrixXd FirstOrderMatrix(const Model& m) {
  const int n = m.dofs();
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  a.topRightCorner(n, n).setIdentity();
  a.bottomLeftCorner(n, n) = -m.mass.inverse() * m.stiffness;
  a.bottomRightCorner(n, n) = -m.mass.inverse() * m.DampingMatrix();
  return a;
}

// 100 ulps of the state's scale: the decomposition and the products each add
// a few ulps, times the eigenvector matrix's condition (~10 here).
constexpr double kRoundOff = 100 * 2.2e-16;

TEST(ForcedFlow, ParticularSolutionIsTheReceptanceResponse) {
  const Model m = DampedForcedPaper();
  const ForcedFlow flow(m);
  for (double t : {0.0, 1.3, 17.0, 250.0}) {
    const Eigen::VectorXd expected = ReceptanceState(m, t);
    EXPECT_LT((flow.Particular(t) - expected).norm(), kRoundOff * expected.norm()) << "t = " << t;
    // Started on it, the flight stays on it.
    Eigen::VectorXd z = ReceptanceState(m, 0.0);
    flow.Advance(0.0, t, z);
    // The phase w t carries ~t ulps.
    EXPECT_LT((z - expected).norm(), kRoundOff * (1.0 + t) * expected.norm()) << "t = " << t;
  }
}

TEST(ForcedFlow, AdvanceMatchesTheMatrixExponential) {
  const Model m = DampedForcedPaper();
  const ForcedFlow flow(m);
  const Eigen::MatrixXd a = FirstOrderMatrix(m);
  Eigen::VectorXd z0(4);
  z0 << 0.3, -0.4, 1.1, 0.2;
  for (double t0 : {0.0, 5.0}) {
    for (double s : {0.01, 1.0, 7.5, 40.0}) {
      Eigen::VectorXd z = z0;
      flow.Advance(t0, s, z);
      const Eigen::VectorXd expected = ReceptanceState(m, t0 + s) + Expm(a, s) * (z0 - ReceptanceState(m, t0));
      EXPECT_LT((z - expected).norm(), kRoundOff * (1.0 + t0 + s) * z0.norm()) << t0 << " " << s;
      EXPECT_LT((flow.Transition(s) - Expm(a, s)).norm(), kRoundOff * (1.0 + s)) << s;
    }
  }
}

TEST(ForcedFlow, ModalDampingGivesTheTextbookEigenvalues) {
  const Model base = PaperModel();
  const std::vector<double> zeta = {0.05, 1.7};  // one underdamped, one overdamped mode
  Model m = base;
  m.damping = ModalDamping(m.mass, m.stiffness, zeta);
  const ModalBasis b = MakeModalBasis(base);
  // Phi' C Phi = diag(2 zeta_i w_i): the definition of modal damping.
  const Eigen::MatrixXd modal = b.phi.transpose() * m.damping * b.phi;
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      EXPECT_NEAR(modal(i, j), i == j ? 2.0 * zeta[i] * b.omega[i] : 0.0, 1e-14);
    }
  }
  const ForcedFlow flow(m);
  const Eigen::VectorXcd lambda = flow.Eigenvalues();
  // Mode 1: -zeta w +- i w sqrt(1 - zeta^2), one of the pair kept;
  // mode 2: two real eigenvalues w (-zeta +- sqrt(zeta^2 - 1)).
  std::vector<Complex> expected = {
      Complex(-zeta[0] * b.omega[0], b.omega[0] * std::sqrt(1.0 - zeta[0] * zeta[0])),
      Complex(b.omega[1] * (-zeta[1] + std::sqrt(zeta[1] * zeta[1] - 1.0)), 0.0),
      Complex(b.omega[1] * (-zeta[1] - std::sqrt(zeta[1] * zeta[1] - 1.0)), 0.0)};
  ASSERT_EQ(lambda.size(), 3);
  for (const Complex& e : expected) {
    double best = 1e300;
    for (int k = 0; k < lambda.size(); ++k) best = std::min(best, std::abs(lambda[k] - e));
    EXPECT_LT(best, 1e-13 * std::abs(e)) << e;
  }
}

TEST(ForcedFlow, SignalFollowsTheFlightAndItsBoundsHold) {
  const Model m = DampedForcedPaper();
  const ForcedFlow flow(m);
  Eigen::VectorXd z0(4);
  z0 << 0.3, -0.4, 1.1, 0.2;
  Eigen::RowVectorXd l(4);
  l << 0.0, 1.0, 0.0, 0.0;  // x2
  DampedSignal g;
  const double t0 = 3.0, c0 = -1.0, c1 = 0.25;
  flow.Observe(t0, z0, l, c0, c1, g);
  for (double s = 0.0; s < 30.0; s += 0.37) {
    Eigen::VectorXd z = z0;
    flow.Advance(t0, s, z);
    const double expected = l.dot(z) + c0 + c1 * std::cos(m.forcing.frequency * (t0 + s));
    EXPECT_NEAR(g.Position(s), expected, kRoundOff * (1.0 + s));
    double d[4];
    g.Derivatives(s, d);
    for (int k = 1; k < 4; ++k) EXPECT_LE(std::abs(d[k]), g.bound[k]) << "k = " << k << ", s = " << s;
    // The velocity is the state's.
    EXPECT_NEAR(d[1], z[3] - c1 * m.forcing.frequency * std::sin(m.forcing.frequency * (t0 + s)),
                kRoundOff * (1.0 + s));
  }
}

TEST(ForcedFlow, UndampedResonanceAndCriticalDampingAreRefused) {
  Model m = PaperModel();
  const ModalBasis b = MakeModalBasis(m);
  m.forcing.amplitude = Eigen::Vector2d(1.0, 0.0);
  m.forcing.frequency = b.omega[0];
  try {
    ForcedFlow flow(m);
    FAIL() << "no error at an undamped resonance";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "forcing.frequency") << e.what();
  }
  // Any damping makes the steady state bounded.
  m.damping = ModalDamping(m.mass, m.stiffness, {1e-3, 1e-3});
  EXPECT_NO_THROW(ForcedFlow{m});
  m.damping = ModalDamping(m.mass, m.stiffness, {1.0, 0.1});
  try {
    ForcedFlow flow(m);
    FAIL() << "no error at critical damping";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "system") << e.what();
    EXPECT_NE(std::string(e.what()).find("critically damped"), std::string::npos) << e.what();
  }
}

using testing::ExpectSceneError;

const char* kChain = "[system]\ngap=1\nrestitution=0.9\nmasses=[1,1]\nsprings=[0.85,2]\n";

TEST(Scene, ReadsTheDampingFormsAndTheForcing) {
  const Scene s = ParseScene(std::string(kChain) +
                             "rayleigh_damping=[0.1, 0.02]\n[forcing]\namplitude=[0.05, 0]\nfrequency=0.6\n"
                             "constant=[0, 0.01]\n");
  EXPECT_LT((s.model.damping - (0.1 * s.model.mass + 0.02 * s.model.stiffness)).norm(), 1e-15);
  EXPECT_EQ(s.model.forcing.amplitude, Eigen::Vector2d(0.05, 0.0));
  EXPECT_EQ(s.model.forcing.constant, Eigen::Vector2d(0.0, 0.01));
  EXPECT_EQ(s.model.forcing.frequency, 0.6);
  const Scene ratios = ParseScene(std::string(kChain) + "damping_ratios=[0.01, 0.02]\n");
  EXPECT_LT((ratios.model.damping - ModalDamping(ratios.model.mass, ratios.model.stiffness, {0.01, 0.02})).norm(),
            1e-15);
  const Scene matrix = ParseScene(std::string(kChain) + "damping_matrix=[[0.1, -0.05], [-0.05, 0.05]]\n");
  EXPECT_EQ(matrix.model.damping(0, 1), -0.05);
  // No damping key and no [forcing]: the paper's conservative model.
  EXPECT_TRUE(ParseScene(kChain).model.Conservative());
}

TEST(Scene, BadDampingAndForcingNameTheFieldAndValue) {
  const std::string c = kChain;
  ExpectSceneError(c + "rayleigh_damping=[-0.1, 0.02]\n", "system.rayleigh_damping", "-0.1");
  ExpectSceneError(c + "rayleigh_damping=[0.1]\n", "system.rayleigh_damping", "1 entries");
  ExpectSceneError(c + "damping_ratios=[0.01]\n", "system.damping_ratios", "(2)");
  ExpectSceneError(c + "damping_ratios=[0.01, -0.2]\n", "system.damping_ratios", "-0.2");
  ExpectSceneError(c + "damping_matrix=[[0.1, 0.05], [0, 0.05]]\n", "system.damping_matrix", "not symmetric");
  ExpectSceneError(c + "damping_matrix=[[0.1, 0.5], [0.5, 0.05]]\n", "system.damping_matrix",
                   "not positive semi-definite");
  ExpectSceneError(c + "damping_matrix=[[0.1]]\n", "system.damping_matrix", "2x2");
  ExpectSceneError(c + "rayleigh_damping=[0, 0.01]\ndamping_ratios=[0.01, 0.01]\n", "system", "at most one");
  ExpectSceneError(c + "[forcing]\namplitude=[1, 0, 0]\nfrequency=1\n", "forcing.amplitude", "3");
  ExpectSceneError(c + "[forcing]\nconstant=[1]\n", "forcing.constant", "1");
  ExpectSceneError(c + "[forcing]\namplitude=[1, 0]\n", "forcing.frequency", "is missing");
  ExpectSceneError(c + "[forcing]\nfrequency=1\n", "forcing.amplitude", "is missing");
  ExpectSceneError(c + "[forcing]\namplitude=[1, 0]\nfrequency=0\n", "forcing.frequency", "0");
  ExpectSceneError(c + "[forcing]\namplitude=[1, 0]\nfrequency=-2\n", "forcing.frequency", "-2");
  ExpectSceneError(c + "[forcing]\namplitude=[1, 0]\nfrequency=1e300\n", "forcing.frequency", "1e+300");
  ExpectSceneError(c + "[forcing]\namplitude=[nan, 0]\nfrequency=1\n", "forcing.amplitude", "nan");
  ExpectSceneError(c + "[forcing]\nphase=1\n", "forcing.phase");
}

TEST(AnalysisBasis, RefusesDampedOrForcedModels) {
  Model m = PaperModel();
  m.damping = RayleighDamping(m.mass, m.stiffness, 0.0, 0.01);
  try {
    AnalysisBasis b(m);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "system") << e.what();
  }
  m = PaperModel();
  m.forcing.constant = Eigen::Vector2d(0.1, 0.0);
  try {
    AnalysisBasis b(m);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "forcing") << e.what();
  }
  // Explicit zeros are the conservative model.
  m.forcing.constant = Eigen::Vector2d::Zero();
  m.damping = Eigen::Matrix2d::Zero();
  EXPECT_NO_THROW(AnalysisBasis{m});
}

}  // namespace
}  // namespace nsmodal
