#include <gtest/gtest.h>

#include "nsmodal/error.h"
#include "nsmodal/model.h"
#include "nsmodal/scene.h"

namespace nsmodal {
namespace {

// The error must name the field, and the offending value where there is one.
void ExpectSceneError(const std::string& toml, const std::string& field, const std::string& value = "") {
  try {
    ParseScene(toml);
    FAIL() << "no error for:\n" << toml;
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(std::string(e.what()).find(value), std::string::npos) << e.what();
  }
}

TEST(Model, ChainMatchesPaperEquation2a) {
  const Model m = PaperModel();
  Eigen::Matrix2d k;
  k << 2.85, -2.0, -2.0, 2.0;
  EXPECT_EQ(m.stiffness, Eigen::MatrixXd(k));
  EXPECT_EQ(m.mass, Eigen::MatrixXd(Eigen::Matrix2d::Identity()));
  EXPECT_EQ(m.contact, 1);
}

TEST(Scene, ParsesChainAndMatrices) {
  const Scene a = ParseScene("[system]\nmasses=[1,1]\nsprings=[0.85,2]\ngap=1\n");
  EXPECT_EQ(a.model.mass, PaperModel().mass);
  EXPECT_EQ(a.model.stiffness, PaperModel().stiffness);
  EXPECT_EQ(a.model.contact, 1);  // default: the last dof
  const Scene b = ParseScene(
      "[system]\nmass_matrix=[[1,0],[0,1]]\nstiffness_matrix=[[2.85,-2],[-2,2]]\ncontact_dof=1\ngap=0.5\n"
      "restitution=0.3\n");
  EXPECT_EQ(b.model.contact, 0);
  EXPECT_DOUBLE_EQ(b.model.gap, 0.5);
  EXPECT_DOUBLE_EQ(b.model.restitution, 0.3);
}

TEST(Scene, BadInputNamesTheFieldAndValue) {
  ExpectSceneError("[system]\nmasses=[1,-1]\nsprings=[1,1]\n", "system.masses", "-1");
  ExpectSceneError("[system]\nmasses=[1,0]\nsprings=[1,1]\n", "system.masses", "0");
  ExpectSceneError("[system]\nmasses=[1,1]\nsprings=[1]\n", "system.springs");
  ExpectSceneError("[system]\nmasses=[1,1]\nsprings=[1,1]\ncontact_dof=3\n", "system.contact_dof", "3");
  ExpectSceneError("[system]\nmasses=[1,1]\nsprings=[1,1]\ncontact_dof=0\n", "system.contact_dof", "0");
  ExpectSceneError("[system]\nmasses=[1,1]\nsprings=[1,1]\ngap=0\n", "system.gap", "0");
  ExpectSceneError("[system]\nmasses=[1,1]\nsprings=[1,1]\ngap=-2\n", "system.gap", "-2");
  ExpectSceneError("[system]\nmasses=[1,1]\nsprings=[1,1]\nrestitution=1.5\n", "system.restitution", "1.5");
  ExpectSceneError("[system]\nmasses=[1,1]\nsprings=[1,1]\nrestitution=-0.1\n", "system.restitution", "-0.1");
  ExpectSceneError("[system]\nmass_matrix=[[1,2],[2,1]]\nstiffness_matrix=[[1,0],[0,1]]\n",
                   "system.mass_matrix", "not positive definite");
  ExpectSceneError("[system]\nmass_matrix=[[1,0],[0,1]]\nstiffness_matrix=[[1,0.5],[0,1]]\n",
                   "system.stiffness_matrix", "not symmetric");
  ExpectSceneError("[system]\nmass_matrix=[[1,0],[0,1]]\nstiffness_matrix=[[1,0],[0]]\n",
                   "system.stiffness_matrix[2]");
  ExpectSceneError("[system]\nmasses=[1,\"a\"]\nsprings=[1,1]\n", "system.masses[2]", "a");
  ExpectSceneError("[system]\nmasses=[1,1]\nspring=[1,1]\n", "system.spring");
  ExpectSceneError("[system]\nmasses=[1,1]\n", "system.springs");
  ExpectSceneError("[other]\nx=1\n", "system");
  ExpectSceneError("[system\nmasses=[1,1]\n", "scene", ":1:");
}

TEST(Scene, MissingFileIsAnInputError) {
  EXPECT_THROW(LoadScene("/nonexistent/scene.toml"), InputError);
}

}  // namespace
}  // namespace nsmodal
