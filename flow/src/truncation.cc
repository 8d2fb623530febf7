#include "nsmodal/truncation.h"

#include <cmath>
#include <limits>
#include <string>

#include "nsmodal/error.h"
#include "nsmodal/modal_basis.h"

namespace nsmodal {
namespace {

// f_res(k) = sum_{i >= k} r_i^2 / w_i^2 for k = 0..N (0-based; f_res(N) = 0),
// summed from the top (the smallest terms first).
Eigen::VectorXd ResidualFlexibilities(const ModalBasis& b) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(b.n + 1);
  for (int i = b.n - 1; i >= 0; --i) {
    f[i] = f[i + 1] + (i < b.rigid ? std::numeric_limits<double>::infinity()
                                   : b.r[i] * b.r[i] / (b.omega[i] * b.omega[i]));
  }
  return f;
}

void CheckModes(const ModalBasis& b, int modes, const std::string& field) {
  // The rigid-body modes and one elastic mode at least (Validate refuses a
  // model without stiffness).
  const int least = b.rigid + 1;
  if (modes < least || modes > b.n) {
    throw InputError(field, std::to_string(modes) + " modes: keep from " + std::to_string(least) + " to " +
                                std::to_string(b.n) + " (the model has " + std::to_string(b.n) + " dofs" +
                                (b.rigid > 0 ? ", " + std::to_string(b.rigid) + " rigid-body mode(s), always kept"
                                             : std::string()) +
                                ")");
  }
}

}  // namespace

Eigen::VectorXd ModalTruncation::PhysicalState(const Eigen::VectorXd& z) const {
  Eigen::VectorXd out(2 * dofs);
  out << to_physical * z.head(kept), to_physical * z.tail(kept);
  return out;
}

double ModalTruncation::ContactBound(double energy) const {
  return std::sqrt(2.0 * std::max(energy, 0.0) * residual_flexibility);
}

namespace {

// TruncateModes on the model's basis, computed once by the caller.
ModalTruncation Truncate(const Model& full, const ModalBasis& b, int modes, const std::string& field) {
  RequireOneContact(full, "modal truncation");
  CheckModes(b, modes, field);
  const int k = modes;
  const Eigen::VectorXd r = b.r.head(k);
  const double norm = r.norm();
  if (!(norm > 1e-12 * std::sqrt(b.r_norm2))) {
    throw InputError(field, std::to_string(k) + " modes: none of them moves the contact dof (its row of the "
                                                "kept mode shapes is zero); keep more modes");
  }
  // Q: orthogonal, first row r / |r| (a Householder reflection, its vector
  // chosen away from cancellation, the first row's sign then restored).
  const Eigen::VectorXd unit = r / norm;
  Eigen::VectorXd w = unit;
  const double sign = unit[0] >= 0.0 ? 1.0 : -1.0;
  w[0] += sign;
  Eigen::MatrixXd q = Eigen::MatrixXd::Identity(k, k) - (2.0 / w.squaredNorm()) * w * w.transpose();
  q.row(0) *= -sign;  // H unit = -sign e_0: its first row is -sign unit'
  const Eigen::MatrixXd phi = b.phi.leftCols(k);
  const double s2 = 1.0 / (norm * norm);

  ModalTruncation t;
  t.kept = k;
  t.dofs = b.n;
  t.highest_kept_frequency = b.omega[k - 1];
  t.lowest_neglected_frequency = k < b.n ? b.omega[k] : std::numeric_limits<double>::infinity();
  t.residual_flexibility = ResidualFlexibilities(b)[k];
  Model& m = t.model;
  m.mass = s2 * Eigen::MatrixXd::Identity(k, k);
  const Eigen::VectorXd w2 = b.omega.head(k).cwiseAbs2();
  m.stiffness = s2 * q * w2.asDiagonal() * q.transpose();
  m.stiffness = 0.5 * (m.stiffness + m.stiffness.transpose()).eval();
  if (full.HasDamping()) {
    m.damping = s2 * q * (phi.transpose() * full.damping * phi) * q.transpose();
    m.damping = 0.5 * (m.damping + m.damping.transpose()).eval();
  }
  if (full.forcing.constant.size() > 0) m.forcing.constant = (q * (phi.transpose() * full.forcing.constant)) / norm;
  if (full.forcing.amplitude.size() > 0) {
    m.forcing.amplitude = (q * (phi.transpose() * full.forcing.amplitude)) / norm;
  }
  m.forcing.frequency = full.forcing.frequency;
  m.contacts = {DofContact(k, 0, true, full.FirstContact().gap, full.FirstContact().restitution)};
  m.contacts.front().shorthand = full.FirstContact().shorthand;
  Validate(m);
  t.to_physical = phi * q.transpose() / norm;
  t.from_physical = norm * q * b.phi_inv.topRows(k);
  return t;
}

// ModesForContactBound on the model's basis.
int ModesFor(const ModalBasis& b, double energy, double tolerance, const std::string& field) {
  if (!(tolerance > 0.0) || !std::isfinite(tolerance)) {
    throw InputError(field, "must be a positive number of metres, got " + FormatValue(tolerance));
  }
  if (!(energy >= 0.0) || !std::isfinite(energy)) {
    throw InputError(field, "needs a finite energy >= 0, got " + FormatValue(energy));
  }
  const Eigen::VectorXd f = ResidualFlexibilities(b);
  for (int k = b.rigid + 1; k < b.n; ++k) {
    if (std::sqrt(2.0 * energy * f[k]) <= tolerance) return k;
  }
  return b.n;
}

}  // namespace

ModalTruncation TruncateModes(const Model& full, int modes, const std::string& field) {
  return Truncate(full, MakeModalBasis(full), modes, field);
}

ModalTruncation TruncateModesAsGiven(const Model& full, double modes, const std::string& field) {
  // Whole and bounded first: casting a fraction, a non-finite or a huge value to an int is wrong or undefined.
  if (modes != std::floor(modes) || !(std::abs(modes) <= kMaxDofs)) {
    throw InputError(field, "must be a whole number of modes, got " + FormatValue(modes));
  }
  return TruncateModes(full, static_cast<int>(modes), field);
}

int ModesForContactBound(const Model& full, double energy, double tolerance, const std::string& field) {
  return ModesFor(MakeModalBasis(full), energy, tolerance, field);
}

ModalTruncation TruncateForContactBound(const Model& full, double energy, double tolerance,
                                        const std::string& field) {
  const ModalBasis b = MakeModalBasis(full);
  return Truncate(full, b, ModesFor(b, energy, tolerance, field), field);
}

}  // namespace nsmodal
