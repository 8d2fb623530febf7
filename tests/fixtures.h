#pragma once
// Shared closed-form problems for the tests.
#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

#include "nsmodal/modal_basis.h"
#include "nsmodal/model.h"

namespace nsmodal::testing {

inline AnalysisBasis PaperBasis() { return AnalysisBasis(PaperModel()); }

// The paper's chain with a third mass on its own spring, uncoupled from the
// contact: every orbit of the 2-dof system is an orbit of this one.
inline Model PaperPlusUncoupledMass() {
  Model m = PaperModel();
  m.mass = Eigen::Matrix3d::Identity();
  m.stiffness = Eigen::Matrix3d::Zero();
  m.stiffness.topLeftCorner(2, 2) = PaperModel().stiffness;
  m.stiffness(2, 2) = 5.0;
  m.contacts = {DofContact(3, 1, true, 1.0, 1.0)};  // the paper's x2 <= 1 in 3 dofs
  m.FirstContact().shorthand = true;
  return m;
}

// A 3-dof system with a full (non-diagonal) SPD mass matrix.
inline Model CoupledThreeDof() {
  Model m;
  m.mass.resize(3, 3);
  m.mass << 2.0, 0.3, 0.1, 0.3, 1.5, 0.2, 0.1, 0.2, 1.0;
  m.stiffness.resize(3, 3);
  m.stiffness << 3.0, -1.0, 0.0, -1.0, 2.5, -0.8, 0.0, -0.8, 1.2;
  m.contacts = {DofContact(m.dofs(), 1, true, 0.7, 1.0)};
  m.FirstContact().shorthand = true;
  return m;
}

// Free flight of M x'' + K x = 0 as the exponential of the first-order
// system matrix: independent of the modal basis.
inline Eigen::MatrixXd PhysicalFlow(const Model& m, double t) {
  const int n = m.dofs();
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  a.topRightCorner(n, n).setIdentity();
  a.bottomLeftCorner(n, n) = -m.mass.ldlt().solve(m.stiffness);
  return (a * t).exp();
}

}  // namespace nsmodal::testing
