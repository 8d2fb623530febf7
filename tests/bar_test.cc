#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "nsmodal/error.h"
#include "nsmodal/modal_basis.h"
#include "nsmodal/model.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/scene.h"

namespace nsmodal {
namespace {

BarSpec Steel(int elements, BarSpec::MassForm mass = BarSpec::MassForm::kConsistent) {
  BarSpec bar;
  bar.length = 1.0;
  bar.youngs_modulus = 210e9;
  bar.density = 7800.0;
  bar.area = 3.14e-4;
  bar.elements = elements;
  bar.mass = mass;
  return bar;
}

// The element matrices assembled by hand for three elements, fixed-free
// (dofs = nodes 1..3): K = (EA/h) tridiag(-1, 2, -1) with K(3,3) = EA/h;
// consistent M = (rho A h / 6) tridiag(1, 4, 1) with M(3,3) = 2 rho A h / 6;
// lumped M = rho A h diag(1, 1, 1/2). Exact to round-off (sums of two terms).
TEST(Bar, MatricesAreTheTextbookOnes) {
  const BarSpec bar = Steel(3);
  const double h = 1.0 / 3.0, k = bar.youngs_modulus * bar.area / h, m = bar.density * bar.area * h;
  Eigen::Matrix3d k_ref, m_ref, lumped_ref;
  k_ref << 2, -1, 0, -1, 2, -1, 0, -1, 1;
  m_ref << 4, 1, 0, 1, 4, 1, 0, 1, 2;
  lumped_ref << 1, 0, 0, 0, 1, 0, 0, 0, 0.5;
  const Model consistent = MakeBar(bar, 2, 1e-4, 1.0);
  EXPECT_LT((consistent.stiffness - k * k_ref).norm(), 1e-15 * k * 3);
  EXPECT_LT((consistent.mass - (m / 6.0) * m_ref).norm(), 1e-15 * m * 3);
  const Model lumped = MakeBar(Steel(3, BarSpec::MassForm::kLumped), 2, 1e-4, 1.0);
  EXPECT_LT((lumped.mass - m * lumped_ref).norm(), 1e-15 * m * 3);
  EXPECT_EQ(consistent.dofs(), 3);
}

// The continuous fixed-free bar has w_k = (2k - 1) pi c / (2 L). Linear
// elements bound the lowest ones from above (consistent mass, Rayleigh-Ritz)
// and, for these modes, from below (lumped mass); both converge as h^2:
// 100 elements put the first frequency within 1e-4 relative (the error is
// ~ (w h / c)^2 / 24 ~ 1e-5 for the first mode).
TEST(Bar, FrequenciesBracketTheContinuousBarAndConvergeAsHSquared) {
  const BarSpec bar = Steel(100);
  const double c = bar.WaveSpeed();
  const ModalBasis consistent = MakeModalBasis(MakeBar(bar, 99, 1e-4, 1.0));
  const ModalBasis lumped = MakeModalBasis(MakeBar(Steel(100, BarSpec::MassForm::kLumped), 99, 1e-4, 1.0));
  for (int mode = 1; mode <= 3; ++mode) {
    const double exact = (2 * mode - 1) * M_PI * c / 2.0;
    EXPECT_GT(consistent.omega[mode - 1], exact) << mode;
    EXPECT_LT(lumped.omega[mode - 1], exact) << mode;
    EXPECT_LT(std::abs(consistent.omega[mode - 1] / exact - 1.0), 1e-3) << mode;
  }
  EXPECT_LT(std::abs(consistent.omega[0] / (M_PI * c / 2.0) - 1.0), 1e-4);
  // h^2: halving the elements multiplies the first mode's error by ~4.
  const ModalBasis coarse = MakeModalBasis(MakeBar(Steel(50), 49, 1e-4, 1.0));
  const double exact = M_PI * c / 2.0;
  EXPECT_NEAR((coarse.omega[0] - exact) / (consistent.omega[0] - exact), 4.0, 0.05);
}

TEST(Bar, SceneBuildsTheBarWithItsContactOnTheFreeEnd) {
  const Scene s = ParseScene(
      "[system]\nbar = { length = 1.0, youngs_modulus = 210e9, density = 7800, area = 3.14e-4, elements = 10 }\n"
      "gap = 1e-4\nrestitution = 1.0\n");
  EXPECT_EQ(s.model.dofs(), 10);
  EXPECT_EQ(s.model.FirstContact().dof, 9);
  EXPECT_LT((s.model.stiffness - MakeBar(Steel(10), 9, 1e-4, 1.0).stiffness).norm(), 1e-6);
  const Scene mid = ParseScene(
      "[system]\nbar = { length = 1.0, youngs_modulus = 210e9, density = 7800, area = 3.14e-4, elements = 10, "
      "mass = \"lumped\" }\ncontact_dof = 5\ngap = 1e-4\nrestitution = 1.0\n");
  EXPECT_EQ(mid.model.FirstContact().dof, 4);
  EXPECT_EQ(mid.model.mass(4, 5), 0.0);
}

std::string FieldOf(const std::string& bar) {
  try {
    ParseScene("[system]\nbar = { " + bar + " }\ngap = 1e-4\nrestitution = 1.0\n");
  } catch (const InputError& e) {
    return e.field() + " | " + e.what();
  }
  return "no error";
}

TEST(Bar, BadInputNamesTheFieldAndTheValue) {
  const std::string base = "length = 1.0, youngs_modulus = 210e9, density = 7800, area = 3.14e-4";
  EXPECT_NE(FieldOf(base + ", elements = 0").find("system.bar.elements | system.bar.elements: must be an integer between 1 and 2000, got 0"),
            std::string::npos);
  EXPECT_NE(FieldOf("length = 1.0, youngs_modulus = -5, density = 7800, area = 3.14e-4, elements = 4")
                .find("system.bar.youngs_modulus | system.bar.youngs_modulus: must be positive and finite, got -5"),
            std::string::npos);
  EXPECT_NE(FieldOf(base + ", elements = 2.5").find("system.bar.elements"), std::string::npos);
  EXPECT_NE(FieldOf(base).find("system.bar.elements | system.bar.elements: is missing"), std::string::npos);
  EXPECT_NE(FieldOf(base + ", elements = 4, boundary = \"clamped\"").find("system.bar.boundary"), std::string::npos);
  EXPECT_NE(FieldOf(base + ", elements = 4, mass = 3").find("system.bar.mass"), std::string::npos);
  EXPECT_NE(FieldOf(base + ", elements = 4, colour = 1").find("system.bar.colour"), std::string::npos);
  // Free-free parses (the simulator flies its rigid-body mode); the analysis
  // refuses it, naming the stiffness and the mode.
  const Scene free = ParseScene("[system]\nbar = { " + base + ", elements = 4, boundary = \"free-free\" }\n"
                                "gap = 1e-4\nrestitution = 1.0\n");
  EXPECT_EQ(free.model.dofs(), 5);
  try {
    const AnalysisBasis b(free.model);
    ADD_FAILURE() << "the analysis accepted a free-free bar";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "system.stiffness_matrix");
    EXPECT_NE(std::string(e.what()).find("1 rigid-body mode"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ParseScene("[system]\nbar = { " + base + ", elements = 4 }\nmasses = [1.0]\nsprings = [1.0]\n"
                          "gap = 1e-4\nrestitution = 1.0\n"),
               InputError);
}

// The 1-ipp nonsmooth mode of the bar: below the first linear period the
// orbits are periodic to the engine's target for 100 elements.
TEST(Bar, OneImpactOrbitsOfAHundredElementBarArePeriodic) {
  const AnalysisBasis b(MakeBar(Steel(100), 99, 1e-4, 1.0));
  const double t1 = b.Periods()[0];
  int potential = 0;
  for (double f = 0.55; f < 1.0; f += 0.05) {
    const Orbit o = OneImpactOrbit(b, f * t1);
    if (!o.potential) continue;
    ++potential;
    EXPECT_LT(o.periodicity_residual, 1e-10) << "T / T1 = " << f;
  }
  EXPECT_GT(potential, 5);
}

}  // namespace
}  // namespace nsmodal
