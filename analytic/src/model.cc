#include "nsmodal/model.h"

#include <cmath>
#include <sstream>

#include "nsmodal/error.h"

namespace nsmodal {

std::string FormatValue(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}

namespace {

// Checks a symmetric positive-definite matrix; returns its extreme eigenvalues.
std::pair<double, double> CheckSpd(const Eigen::MatrixXd& a, const std::string& field) {
  if (a.rows() == 0 || a.rows() != a.cols()) {
    throw InputError(field, "must be a non-empty square matrix, got " +
                                std::to_string(a.rows()) + "x" + std::to_string(a.cols()));
  }
  if (!a.allFinite()) throw InputError(field, "has a non-finite entry");
  // Symmetry relative to the largest entry: a matrix typed with 16 digits is
  // symmetric to ~1e-15; 1e-12 leaves room for that and rejects real asymmetry.
  const double scale = a.cwiseAbs().maxCoeff();
  const double asym = (a - a.transpose()).cwiseAbs().maxCoeff();
  if (asym > 1e-12 * scale) {
    throw InputError(field, "is not symmetric (max |A - A^T| = " + FormatValue(asym) + ")");
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(a, Eigen::EigenvaluesOnly);
  const double lmin = eig.eigenvalues().minCoeff(), lmax = eig.eigenvalues().maxCoeff();
  if (!(lmin > 0.0)) {
    throw InputError(field, "is not positive definite (smallest eigenvalue " + FormatValue(lmin) + ")");
  }
  return {lmin, lmax};
}

}  // namespace

Model MakeChain(const std::vector<double>& masses, const std::vector<double>& springs,
                int contact, double gap, double restitution) {
  if (masses.size() > static_cast<std::size_t>(kMaxDofs)) {
    throw InputError("system.masses", "lists " + std::to_string(masses.size()) + " masses; nsmodal honours up to " +
                                          std::to_string(kMaxDofs));
  }
  const int n = static_cast<int>(masses.size());
  if (n == 0) throw InputError("system.masses", "must list at least one mass");
  if (static_cast<int>(springs.size()) != n) {
    throw InputError("system.springs", "must have as many entries as system.masses (" +
                                           std::to_string(n) + "), got " +
                                           std::to_string(springs.size()));
  }
  for (int i = 0; i < n; ++i) {
    if (!(masses[i] > 0.0) || !std::isfinite(masses[i])) {
      throw InputError("system.masses", "entry " + std::to_string(i + 1) +
                                            " must be positive and finite, got " + FormatValue(masses[i]));
    }
    if (!(springs[i] > 0.0) || !std::isfinite(springs[i])) {
      throw InputError("system.springs", "entry " + std::to_string(i + 1) +
                                             " must be positive and finite, got " + FormatValue(springs[i]));
    }
  }
  Model m;
  m.mass = Eigen::MatrixXd::Zero(n, n);
  m.stiffness = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    m.mass(i, i) = masses[i];
    m.stiffness(i, i) += springs[i];
    if (i > 0) {
      m.stiffness(i - 1, i - 1) += springs[i];
      m.stiffness(i - 1, i) -= springs[i];
      m.stiffness(i, i - 1) -= springs[i];
    }
  }
  m.contact = contact;
  m.gap = gap;
  m.restitution = restitution;
  Validate(m);
  return m;
}

Model PaperModel() { return MakeChain({1.0, 1.0}, {0.85, 2.0}, 1, 1.0, 1.0); }

void Validate(const Model& model) {
  if (model.mass.rows() > kMaxDofs) {
    throw InputError("system.mass_matrix", "has " + std::to_string(model.mass.rows()) +
                                               " rows; nsmodal honours up to " + std::to_string(kMaxDofs) + " dofs");
  }
  const auto [mass_min, mass_max] = CheckSpd(model.mass, "system.mass_matrix");
  const auto [stiffness_min, stiffness_max] = CheckSpd(model.stiffness, "system.stiffness_matrix");
  if (mass_max > kMaxCondition * mass_min) {
    throw InputError("system.mass_matrix", "is too close to singular: eigenvalues from " + FormatValue(mass_min) +
                                               " to " + FormatValue(mass_max) + " (nsmodal honours a ratio up to " +
                                               FormatValue(kMaxCondition) + ")");
  }
  if (stiffness_max > kMaxCondition * stiffness_min) {
    throw InputError("system.stiffness_matrix", "is too close to singular: eigenvalues from " +
                                                    FormatValue(stiffness_min) + " to " + FormatValue(stiffness_max) +
                                                    " (nsmodal honours a ratio up to " + FormatValue(kMaxCondition) +
                                                    ")");
  }
  if (model.stiffness.rows() != model.mass.rows()) {
    throw InputError("system.stiffness_matrix", "must have the size of system.mass_matrix (" +
                                                    std::to_string(model.mass.rows()) + ")");
  }
  if (model.contact < 0 || model.contact >= model.dofs()) {
    throw InputError("system.contact_dof", "must be between 1 and " + std::to_string(model.dofs()) +
                                               ", got " + std::to_string(model.contact + 1));
  }
  if (!(model.gap > 0.0) || !std::isfinite(model.gap)) {
    throw InputError("system.gap", "must be positive and finite, got " + FormatValue(model.gap));
  }
  // The energy of a state at the obstacle, K d^2 / 2, must leave room for
  // impact velocities and sums: at most kMaxEnergyScale.
  const double energy_scale = 0.5 * stiffness_max * model.gap * model.gap;
  if (!(energy_scale <= kMaxEnergyScale) || !(energy_scale >= 1.0 / kMaxEnergyScale)) {
    throw InputError("system.gap", "gives energies of order " + FormatValue(energy_scale) +
                                       " (K d^2 / 2); nsmodal honours 1e-200 to 1e200: rescale the units");
  }
  if (!(model.restitution >= 0.0 && model.restitution <= 1.0)) {
    throw InputError("system.restitution", "must lie in [0, 1], got " + FormatValue(model.restitution));
  }
}

}  // namespace nsmodal
