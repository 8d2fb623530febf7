#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "nsmodal/error.h"
#include "nsmodal/modal_basis.h"
#include "nsmodal/model.h"
#include "nsmodal/model_spec.h"
#include "nsmodal/roots.h"
#include "nsmodal/scene.h"
#include "scene_errors.h"

namespace nsmodal {
namespace {

using testing::ExpectSceneError;

TEST(Model, ChainMatchesPaperEquation2a) {
  const Model m = PaperModel();
  Eigen::Matrix2d k;
  k << 2.85, -2.0, -2.0, 2.0;
  EXPECT_EQ(m.stiffness, Eigen::MatrixXd(k));
  EXPECT_EQ(m.mass, Eigen::MatrixXd(Eigen::Matrix2d::Identity()));
  EXPECT_EQ(m.FirstContact().dof, 1);
}

// The tridiagonal path of SymmetricEigenvalues (chains, bars) against the
// dense one on the same matrix: both are backward stable, so they agree to a
// few ulps of the largest eigenvalue (1e-13 relative leaves a factor ~50 of
// room at N = 200). One entry off the band sends a matrix down the dense path,
// which must then see it (here it moves the spectrum by far more than that).
TEST(Model, TridiagonalEigenvaluesMatchTheDenseSolver) {
  const int n = 200;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    a(i, i) = 2.0 + std::sin(1.0 + i);
    if (i + 1 < n) a(i, i + 1) = a(i + 1, i) = -1.0 + 0.3 * std::cos(2.0 * i);
  }
  const auto dense = [](const Eigen::MatrixXd& m) {
    return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(m, Eigen::EigenvaluesOnly).eigenvalues();
  };
  const double scale = dense(a).cwiseAbs().maxCoeff();
  EXPECT_LT((SymmetricEigenvalues(a) - dense(a)).cwiseAbs().maxCoeff(), 1e-13 * scale);
  a(0, n - 1) = a(n - 1, 0) = 0.5;
  EXPECT_LT((SymmetricEigenvalues(a) - dense(a)).cwiseAbs().maxCoeff(), 1e-13 * scale);
  Eigen::MatrixXd band = a;
  band(0, n - 1) = band(n - 1, 0) = 0.0;
  EXPECT_GT((SymmetricEigenvalues(a) - SymmetricEigenvalues(band)).cwiseAbs().maxCoeff(), 1e-3);
  // A 1x1 matrix is its own eigenvalue.
  EXPECT_EQ(SymmetricEigenvalues(Eigen::MatrixXd::Constant(1, 1, 3.0))[0], 3.0);
}

TEST(Scene, ParsesChainAndMatrices) {
  const Scene a = ParseScene("[system]\nrestitution=1\nmasses=[1,1]\nsprings=[0.85,2]\ngap=1\n");
  EXPECT_EQ(a.model.mass, PaperModel().mass);
  EXPECT_EQ(a.model.stiffness, PaperModel().stiffness);
  EXPECT_EQ(a.model.FirstContact().dof, 1);  // default: the last dof
  const Scene b = ParseScene(
      "[system]\nmass_matrix=[[1,0],[0,1]]\nstiffness_matrix=[[2.85,-2],[-2,2]]\ncontact_dof=1\ngap=0.5\n"
      "restitution=0.3\n");
  EXPECT_EQ(b.model.FirstContact().dof, 0);
  EXPECT_DOUBLE_EQ(b.model.FirstContact().gap, 0.5);
  EXPECT_DOUBLE_EQ(b.model.FirstContact().restitution, 0.3);
}

TEST(Scene, BadInputNamesTheFieldAndValue) {
  ExpectSceneError("[system]\ngap=1\nrestitution=1\nmasses=[1,-1]\nsprings=[1,1]\n", "system.masses", "-1");
  ExpectSceneError("[system]\ngap=1\nrestitution=1\nmasses=[1,0]\nsprings=[1,1]\n", "system.masses", "0");
  ExpectSceneError("[system]\ngap=1\nrestitution=1\nmasses=[1,1]\nsprings=[1]\n", "system.springs");
  ExpectSceneError("[system]\ngap=1\nrestitution=1\nmasses=[1,1]\nsprings=[1,1]\ncontact_dof=3\n", "system.contact_dof", "3");
  ExpectSceneError("[system]\ngap=1\nrestitution=1\nmasses=[1,1]\nsprings=[1,1]\ncontact_dof=0\n", "system.contact_dof", "0");
  ExpectSceneError("[system]\nrestitution=1\nmasses=[1,1]\nsprings=[1,1]\ngap=0\n", "system.gap", "0");
  ExpectSceneError("[system]\nrestitution=1\nmasses=[1,1]\nsprings=[1,1]\ngap=-2\n", "system.gap", "-2");
  ExpectSceneError("[system]\ngap=1\nmasses=[1,1]\nsprings=[1,1]\nrestitution=1.5\n", "system.restitution", "1.5");
  ExpectSceneError("[system]\ngap=1\nmasses=[1,1]\nsprings=[1,1]\nrestitution=-0.1\n", "system.restitution", "-0.1");
  ExpectSceneError("[system]\ngap=1\nrestitution=1\nmass_matrix=[[1,2],[2,1]]\nstiffness_matrix=[[1,0],[0,1]]\n",
                   "system.mass_matrix", "not positive definite");
  ExpectSceneError("[system]\ngap=1\nrestitution=1\nmass_matrix=[[1,0],[0,1]]\nstiffness_matrix=[[1,0.5],[0,1]]\n",
                   "system.stiffness_matrix", "not symmetric");
  ExpectSceneError("[system]\ngap=1\nrestitution=1\nmass_matrix=[[1,0],[0,1]]\nstiffness_matrix=[[1,0],[0]]\n",
                   "system.stiffness_matrix[2]");
  ExpectSceneError("[system]\ngap=1\nrestitution=1\nmasses=[1,\"a\"]\nsprings=[1,1]\n", "system.masses[2]", "a");
  ExpectSceneError("[system]\ngap=1\nrestitution=1\nmasses=[1,1]\nspring=[1,1]\n", "system.spring");
  // Issue 14: no silent defaults for the obstacle and the impact law.
  ExpectSceneError("[system]\nrestitution=1\nmasses=[1,1]\nsprings=[1,1]\n", "system.gap", "is missing");
  ExpectSceneError("[system]\ngap=1\nmasses=[1,1]\nsprings=[1,1]\n", "system.restitution", "is missing");
  // Issue 14: a contact_dof of nan, inf or 1e20 was cast to an integer (undefined behaviour).
  ExpectSceneError("[system]\ngap=1\nrestitution=1\nmasses=[1,1]\nsprings=[1,1]\ncontact_dof=nan\n",
                   "system.contact_dof", "nan");
  ExpectSceneError("[system]\ngap=1\nrestitution=1\nmasses=[1,1]\nsprings=[1,1]\ncontact_dof=inf\n",
                   "system.contact_dof", "inf");
  ExpectSceneError("[system]\ngap=1\nrestitution=1\nmasses=[1,1]\nsprings=[1,1]\ncontact_dof=1e20\n",
                   "system.contact_dof", "1e+20");
  ExpectSceneError("[system]\ngap=1\nrestitution=1\nmasses=[1,1]\nsprings=[1,1]\ncontact_dof=1.5\n",
                   "system.contact_dof", "1.5");
  ExpectSceneError("[system]\ngap=1\nrestitution=1\nmasses=[1,1]\n", "system.springs");
  ExpectSceneError("[other]\nx=1\n", "system");
  ExpectSceneError("[system\nmasses=[1,1]\n", "scene", ":1:");
}

// One assembly for both faces (model_spec.h): the scene and the Python
// module build the same model from the same keys, and each names a field as
// its user wrote it.
TEST(AssembleModel, TheFacesShareTheRulesAndNameTheirOwnFields) {
  ModelSpec spec;
  spec.masses = {1.0, 1.0};
  spec.springs = {0.85, 2.0};
  spec.gap = 1.0;
  spec.restitution = 0.8;
  spec.damping_ratios = {0.02, 0.02};
  spec.forcing_amplitude = {0.3, 0.0};
  spec.forcing_frequency = 0.5;
  const Scene scene = ParseScene("[system]\nmasses=[1,1]\nsprings=[0.85,2]\ngap=1\nrestitution=0.8\n"
                                 "damping_ratios=[0.02,0.02]\n[forcing]\namplitude=[0.3,0]\nfrequency=0.5\n");
  const Model m = AssembleModel(spec, FieldNames("system."));
  EXPECT_EQ(m.damping, scene.model.damping);
  EXPECT_EQ(m.forcing.amplitude, scene.model.forcing.amplitude);
  EXPECT_EQ(m.FirstContact().dof, 1);
  auto field = [](const ModelSpec& s, const FieldNames& names) {
    try {
      AssembleModel(s, names);
    } catch (const InputError& e) {
      return e.field();
    }
    return std::string("no error");
  };
  const FieldNames keywords = FieldNames().Set("form", "masses");
  ModelSpec two = spec;
  two.rayleigh_damping = {0.1, 0.0};
  EXPECT_EQ(field(two, keywords), "damping");
  ModelSpec chain_and_matrix = spec;
  chain_and_matrix.mass_matrix = Eigen::MatrixXd::Identity(2, 2);
  EXPECT_EQ(field(chain_and_matrix, keywords), "masses");
  ModelSpec no_springs = spec;
  no_springs.springs.reset();
  EXPECT_EQ(field(no_springs, keywords), "springs");
  EXPECT_EQ(field(no_springs, FieldNames("system.")), "system.springs");
  ModelSpec no_frequency = spec;
  no_frequency.forcing_frequency.reset();
  EXPECT_EQ(field(no_frequency, keywords), "forcing.frequency");
  ModelSpec bad_contact = spec;
  bad_contact.contact_dof = 3;
  EXPECT_EQ(field(bad_contact, FieldNames("system.")), "system.contact_dof");
}

TEST(Scene, MissingFileIsAnInputError) {
  EXPECT_THROW(LoadScene("/nonexistent/scene.toml"), InputError);
}

// Issue 29 (5): the scene reader reads regular files only, at most
// kMaxSceneBytes, and cannot block: /dev/zero was read until memory ran out,
// a FIFO without a writer hung, a path with a NUL opened another file.
void ExpectReadError(const std::string& path, const std::string& fragment, const std::string& field = "scene") {
  try {
    ReadSceneFile(path, field);
    FAIL() << "read " << path;
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("nsmodal_scene_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

TEST(Scene, TheReaderRefusesDevicesDirectoriesFifosAndNulsNamingThePath) {
  ExpectReadError("/dev/zero", "'/dev/zero' is a character device");
  ExpectReadError("/dev/urandom", "'/dev/urandom' is a character device", "path");
  ExpectReadError("/tmp", "'/tmp' is a directory");
  ExpectReadError(std::string("configs/paper.toml\0x", 20), "'configs/paper.toml\\x00x' holds a NUL", "path");
  ExpectReadError("", "is empty");
  const std::string fifo = TempPath("fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  ExpectReadError(fifo, "'" + fifo + "' is a FIFO");  // returns at once: no writer is waited for
  std::filesystem::remove(fifo);
}

TEST(Scene, TheReaderRefusesAFileLargerThanTheLimitAndReadsOneAtIt) {
  const std::string path = TempPath("big.toml");
  const std::string text = "[system]\nrestitution=1\nmasses=[1,1]\nsprings=[0.85,2]\ngap=1\n";
  {
    std::ofstream out(path, std::ios::binary);
    out << text;
  }
  // Padded with spaces (TOML whitespace) to exactly the limit: accepted.
  std::filesystem::resize_file(path, kMaxSceneBytes);
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(text.size()));
    const std::string pad(kMaxSceneBytes - text.size(), ' ');
    f.write(pad.data(), static_cast<std::streamsize>(pad.size()));
  }
  EXPECT_EQ(ReadSceneFile(path).size(), kMaxSceneBytes);
  std::filesystem::resize_file(path, kMaxSceneBytes + 1);
  ExpectReadError(path, "is 16777217 bytes: a scene file holds at most 16777216 bytes");
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace nsmodal

namespace nsmodal {
namespace {

// Issue 14: scales nsmodal cannot honour are refused with the field named,
// instead of a segfault (a subnormal mass), a hang (NC3 isolation with one
// frequency 1e8 times another) or inf/NaN energies (gap = 1e308).
void ExpectModelError(const std::vector<double>& masses, const std::vector<double>& springs, double gap,
                      const std::string& field, const std::string& fragment) {
  try {
    const Model m = MakeChain(masses, springs, 1, gap, 1.0);
    const ModalBasis b = MakeModalBasis(m);
    FAIL() << "accepted masses " << masses[0] << ", " << masses[1] << " gap " << gap;
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(Model, ScalesOutsideWhatIsHonouredAreRefused) {
  const std::vector<double> unit{1.0, 1.0};
  ExpectModelError({5e-324, 1.0}, unit, 1.0, "system.mass_matrix", "too close to singular");
  ExpectModelError({1.0, 1e-300}, unit, 1.0, "system.mass_matrix", "too close to singular");
  ExpectModelError({1.0, 1e-16}, unit, 1.0, "system.mass_matrix", "too close to singular");
  ExpectModelError(unit, {1.0, 1e13}, 1.0, "system.stiffness_matrix", "too close to singular");
  // M and K each within 1e12 but the frequencies 4.5e6 apart (> 1e6).
  ExpectModelError({1.0, 1e-11}, {1.0, 100.0}, 1.0, "system", "frequencies");
  ExpectModelError(unit, unit, 1e308, "system.gap", "energies");
  ExpectModelError(unit, unit, 1e-160, "system.gap", "energies");
  // Inside the ranges: accepted.
  EXPECT_NO_THROW(MakeModalBasis(MakeChain({1.0, 1e-10}, unit, 1, 1.0, 1.0)));
}

}  // namespace
}  // namespace nsmodal

namespace nsmodal {
namespace {

// Issue 10: the invariant checks were asserts, compiled out in every build the
// project configures. NSMODAL_CHECK is armed in release builds too: a root
// polish without a bracket is a bug of the caller, and aborts saying where.
TEST(CheckDeathTest, AnInternalInvariantAbortsWithFileAndLine) {
  EXPECT_DEATH(PolishRoot([](double t) { return t * t + 1.0; }, -1.0, 1.0),
               "internal invariant violated: .*roots.cc:[0-9]+");
}

}  // namespace
}  // namespace nsmodal
