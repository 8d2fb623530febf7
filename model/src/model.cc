#include "nsmodal/model.h"

#include <cmath>
#include <cstdio>
#include <utility>
#include <sstream>
#include <Eigen/Eigenvalues>

#include "nsmodal/error.h"

namespace nsmodal {

std::string FormatValue(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}

std::string FormatEstimate(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

namespace {

// Checks a square, finite, symmetric matrix; returns its eigenvalues.
Eigen::VectorXd CheckedEigenvalues(const Eigen::MatrixXd& a, const std::string& field) {
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
  return SymmetricEigenvalues(a);
}

// Checks a symmetric positive-definite matrix; returns its extreme eigenvalues.
std::pair<double, double> CheckSpd(const Eigen::MatrixXd& a, const std::string& field) {
  const Eigen::VectorXd eig = CheckedEigenvalues(a, field);
  const double lmin = eig.minCoeff(), lmax = eig.maxCoeff();
  if (!(lmin > 0.0)) {
    throw InputError(field, "is not positive definite (smallest eigenvalue " + FormatValue(lmin) + ")");
  }
  return {lmin, lmax};
}

int CountRigid(const Eigen::VectorXd& eig) {
  const double lmax = eig.maxCoeff();
  return static_cast<int>((eig.array() <= kRigidBodyTolerance * lmax).count());
}

// The contacts' own checks and those of pairs (Validate's, model.h).
void ValidateContacts(const Model& model, double stiffness_max) {
  const int n = model.dofs();
  if (model.contacts.empty()) throw InputError("contact", "none given: a vibro-impact model needs at least one contact");
  for (int j = 0; j < model.NumContacts(); ++j) {
    const Contact& c = model.contacts[j];
    auto field = [&](const char* f) { return ContactField(c, j, f); };
    if (c.form != Contact::Form::kNormal && (c.dof < 0 || c.dof >= n)) {
      throw InputError(field(c.form == Contact::Form::kDof ? "dof" : "between"),
                       "must name dofs between 1 and " + std::to_string(n) + ", got " + std::to_string(c.dof + 1));
    }
    if (c.form == Contact::Form::kBetween && (c.other < 0 || c.other >= n || c.other == c.dof)) {
      throw InputError(field("between"), "must name two different dofs between 1 and " + std::to_string(n) +
                                             ", got " + std::to_string(c.dof + 1) + " and " +
                                             std::to_string(c.other + 1));
    }
    if (c.normal.size() != n) {
      throw InputError(field("normal"), "must have " + std::to_string(n) + " entries (one per dof), got " +
                                            std::to_string(c.normal.size()));
    }
    if (!c.normal.allFinite()) throw InputError(field("normal"), "has a non-finite entry");
    // The dof and between forms read their dofs (Along, RowOf), the rest of
    // nsmodal the normal: the two must say the same wall.
    if (c.form != Contact::Form::kNormal) {
      const Contact expected = c.form == Contact::Form::kDof ? DofContact(n, c.dof, c.upper, c.gap, c.restitution)
                                                             : BetweenContact(n, c.dof, c.other, c.gap, c.restitution);
      if (c.normal != expected.normal) {
        throw InputError(field("normal"), "does not match the contact's form " + expected.Describe() +
                                              " (a contact's normal is built from its dof or pair)");
      }
    }
    if (!(c.normal.cwiseAbs().maxCoeff() > 0.0)) {
      throw InputError(field("normal"), "is zero: a contact needs a direction (g = gap - normal . x)");
    }
    if (!(c.gap > 0.0) || !std::isfinite(c.gap)) {
      // Opposing walls written with a sign (a lower wall at x = -1 given as gap = -1) leave no room.
      for (int k = 0; k < model.NumContacts(); ++k) {
        const Contact& o = model.contacts[k];
        if (k != j && o.normal.size() == n && o.normal.dot(c.normal) < 0.0 &&
            std::abs(o.normal.dot(c.normal)) >= (1.0 - 1e-12) * o.normal.norm() * c.normal.norm()) {
          throw InputError(field("gap"), "must be positive (the distance from rest to the wall), got " +
                                             FormatValue(c.gap) + ": with contact " + std::to_string(k + 1) +
                                             " opposite (" + o.Describe() + ") it leaves no room between the walls");
        }
      }
      throw InputError(field("gap"), "must be positive and finite (the distance from rest to the wall), got " +
                                         FormatValue(c.gap));
    }
    // The energy of a state at the obstacle, K d^2 / 2 (d the distance along
    // the unit normal), must leave room for impact velocities and sums.
    const double distance = c.gap / c.normal.norm();
    const double energy_scale = 0.5 * stiffness_max * distance * distance;
    if (!(energy_scale <= kMaxEnergyScale) || !(energy_scale >= 1.0 / kMaxEnergyScale)) {
      throw InputError(field("gap"), "gives energies of order " + FormatValue(energy_scale) +
                                         " (K d^2 / 2); nsmodal honours 1e-200 to 1e200: rescale the units");
    }
    if (!(c.restitution >= 0.0 && c.restitution <= 1.0)) {
      throw InputError(field("restitution"), "must lie in [0, 1], got " + FormatValue(c.restitution));
    }
  }
  // Pairs: the same direction (a duplicate: one wall hides the other) or
  // opposite walls closer than round-off of their distances.
  for (int j = 0; j < model.NumContacts(); ++j) {
    for (int k = j + 1; k < model.NumContacts(); ++k) {
      const Contact &a = model.contacts[j], &b = model.contacts[k];
      const double na = a.normal.norm(), nb = b.normal.norm(), cosine = a.normal.dot(b.normal) / (na * nb);
      if (cosine >= 1.0 - 1e-12) {
        throw InputError(ContactField(b, k, "normal"),
                         "duplicates contact " + std::to_string(j + 1) + ": " + b.Describe() + " and " + a.Describe() +
                             " are walls facing the same way, so one hides the other; give each wall once");
      }
      if (cosine <= -1.0 + 1e-12) {
        const double room = a.gap / na + b.gap / nb;
        if (!(room > 1e-12 * std::max(a.gap / na, b.gap / nb))) {
          throw InputError(ContactField(b, k, "gap"), "leaves no room between the opposite walls of contacts " +
                                                          std::to_string(j + 1) + " and " + std::to_string(k + 1) +
                                                          " (clearance " + FormatValue(room) + ")");
        }
      }
    }
  }
}

}  // namespace

Eigen::RowVectorXd Contact::RowOf(const Eigen::Ref<const Eigen::MatrixXd>& a) const {
  switch (form) {
    case Form::kDof: return upper ? Eigen::RowVectorXd(a.row(dof)) : Eigen::RowVectorXd(-a.row(dof));
    case Form::kBetween: return a.row(dof) - a.row(other);
    case Form::kNormal: break;
  }
  return normal.transpose() * a;
}

std::string Contact::Describe() const {
  // (A stream: GCC 12 warns falsely (-Wrestrict) on chains of string + literal.)
  std::ostringstream os;
  switch (form) {
    case Form::kDof: os << "x" << dof + 1 << (upper ? " <= " : " >= -"); break;
    case Form::kBetween: os << "x" << dof + 1 << " - x" << other + 1 << " <= "; break;
    case Form::kNormal: os << "n . x <= "; break;
  }
  os << FormatValue(gap);
  return os.str();
}

int Contact::PlotDof() const {
  if (form != Form::kNormal) return dof;
  Eigen::Index i = 0;
  normal.cwiseAbs().maxCoeff(&i);
  return static_cast<int>(i);
}

namespace {
Contact MadeContact(Contact::Form form, Eigen::VectorXd normal, double gap, double restitution) {
  Contact c;
  c.form = form;
  c.normal = std::move(normal);
  c.gap = gap;
  c.restitution = restitution;
  return c;
}
}  // namespace

Contact DofContact(int n, int dof, bool upper, double gap, double restitution) {
  Eigen::VectorXd normal = Eigen::VectorXd::Zero(n);
  if (dof >= 0 && dof < n) normal[dof] = upper ? 1.0 : -1.0;
  Contact c = MadeContact(Contact::Form::kDof, std::move(normal), gap, restitution);
  c.dof = dof;
  c.upper = upper;
  return c;
}

Contact BetweenContact(int n, int dof, int other, double gap, double restitution) {
  Eigen::VectorXd normal = Eigen::VectorXd::Zero(n);
  if (dof >= 0 && dof < n) normal[dof] += 1.0;
  if (other >= 0 && other < n) normal[other] -= 1.0;
  Contact c = MadeContact(Contact::Form::kBetween, std::move(normal), gap, restitution);
  c.dof = dof;
  c.other = other;
  return c;
}

Contact NormalContact(Eigen::VectorXd normal, double gap, double restitution) {
  Contact c = MadeContact(Contact::Form::kNormal, std::move(normal), gap, restitution);
  c.dof = -1;
  return c;
}

std::string ContactField(const Contact& contact, int j, const std::string& field) {
  if (contact.shorthand) return "system." + (field == "dof" ? std::string("contact_dof") : field);
  return "contact[" + std::to_string(j + 1) + "]." + field;
}

bool Model::AllRestitution(double e) const {
  for (const Contact& c : contacts) {
    if (c.restitution != e) return false;
  }
  return true;
}

void RequireOneContact(const Model& model, const std::string& what) {
  if (model.NumContacts() != 1) {
    throw InputError("contact", what + " takes a model with one contact; this one has " +
                                    std::to_string(model.NumContacts()));
  }
}

// Validate paid the dense reduction four times per scene: seconds for a bar of
// 2,000 elements, and past libFuzzer's limit under the sanitizers.
Eigen::VectorXd SymmetricEigenvalues(const Eigen::MatrixXd& a) {
  const Eigen::Index n = a.rows();
  bool tridiagonal = true;
  for (Eigen::Index j = 0; j < n && tridiagonal; ++j) {
    for (Eigen::Index i = 0; i < n; ++i) {
      if ((i > j + 1 || j > i + 1) && a(i, j) != 0.0) {
        tridiagonal = false;
        break;
      }
    }
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig;
  if (tridiagonal && n > 1) {
    const Eigen::VectorXd sub = a.diagonal(-1);
    eig.computeFromTridiagonal(a.diagonal(), sub, Eigen::EigenvaluesOnly);
  } else {
    eig.compute(a, Eigen::EigenvaluesOnly);
  }
  return eig.eigenvalues();
}

int RigidBodyModes(const Eigen::MatrixXd& stiffness) {
  return CountRigid(SymmetricEigenvalues(stiffness));
}

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
    // A zero spring leaves a rigid-body mode (k_1 = 0: no spring to ground).
    if (!(springs[i] >= 0.0) || !std::isfinite(springs[i])) {
      throw InputError("system.springs", "entry " + std::to_string(i + 1) +
                                             " must be non-negative and finite, got " + FormatValue(springs[i]));
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
  m.contacts = {DofContact(n, contact, true, gap, restitution)};
  m.contacts.front().shorthand = true;
  Validate(m);
  return m;
}

double BarSpec::WaveSpeed() const { return std::sqrt(youngs_modulus / density); }

namespace {
template <typename Enum>
Enum OneOf(const std::string& text, const std::string& field, const char* a, Enum ea, const char* b, Enum eb) {
  if (text == a) return ea;
  if (text == b) return eb;
  throw InputError(field, std::string("must be \"") + a + "\" or \"" + b + "\", got \"" + text + "\"");
}
}  // namespace

BarSpec::Boundary ParseBarBoundary(const std::string& text, const std::string& field) {
  return OneOf(text, field, "fixed-free", BarSpec::Boundary::kFixedFree, "free-free", BarSpec::Boundary::kFreeFree);
}

BarSpec::MassForm ParseBarMass(const std::string& text, const std::string& field) {
  return OneOf(text, field, "consistent", BarSpec::MassForm::kConsistent, "lumped", BarSpec::MassForm::kLumped);
}

Model MakeBar(const BarSpec& bar, int contact, double gap, double restitution) {
  const std::pair<const char*, double> positive[] = {{"length", bar.length},
                                                     {"youngs_modulus", bar.youngs_modulus},
                                                     {"density", bar.density},
                                                     {"area", bar.area}};
  for (const auto& [name, value] : positive) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      throw InputError(std::string("system.bar.") + name, "must be positive and finite, got " + FormatValue(value));
    }
  }
  if (bar.elements < 1 || bar.Dofs() > kMaxDofs) {
    throw InputError("system.bar.elements", "must be between 1 and " +
                                                std::to_string(bar.boundary == BarSpec::Boundary::kFixedFree ? kMaxDofs
                                                                                                             : kMaxDofs - 1) +
                                                " (one dof per free node), got " + std::to_string(bar.elements));
  }
  const int n = bar.Dofs();
  const double h = bar.length / bar.elements;
  const double k = bar.youngs_modulus * bar.area / h;
  const double m = bar.density * bar.area * h;
  // Element e joins nodes e and e + 1; node j is dof j - shift (node 0 clamped for fixed-free).
  const int shift = bar.boundary == BarSpec::Boundary::kFixedFree ? 1 : 0;
  const bool consistent = bar.mass == BarSpec::MassForm::kConsistent;
  const double m_diag = consistent ? m / 3.0 : m / 2.0, m_off = consistent ? m / 6.0 : 0.0;
  Model model;
  model.mass = Eigen::MatrixXd::Zero(n, n);
  model.stiffness = Eigen::MatrixXd::Zero(n, n);
  for (int e = 0; e < bar.elements; ++e) {
    const int dof[2] = {e - shift, e + 1 - shift};
    for (int a = 0; a < 2; ++a) {
      if (dof[a] < 0) continue;
      for (int c = 0; c < 2; ++c) {
        if (dof[c] < 0) continue;
        model.stiffness(dof[a], dof[c]) += a == c ? k : -k;
        model.mass(dof[a], dof[c]) += a == c ? m_diag : m_off;
      }
    }
  }
  model.contacts = {DofContact(n, contact, true, gap, restitution)};
  model.contacts.front().shorthand = true;
  Validate(model);
  return model;
}

Model PaperModel() { return MakeChain({1.0, 1.0}, {0.85, 2.0}, 1, 1.0, 1.0); }

int Validate(const Model& model) {
  if (model.mass.rows() > kMaxDofs) {
    throw InputError("system.mass_matrix", "has " + std::to_string(model.mass.rows()) +
                                               " rows; nsmodal honours up to " + std::to_string(kMaxDofs) + " dofs");
  }
  const auto [mass_min, mass_max] = CheckSpd(model.mass, "system.mass_matrix");
  // K: positive semi-definite; its zero eigenvalues are rigid-body modes and
  // the conditioning is that of the others.
  const Eigen::VectorXd k_eig = CheckedEigenvalues(model.stiffness, "system.stiffness_matrix");
  const double stiffness_max = k_eig.maxCoeff();
  if (!(stiffness_max > 0.0)) {
    throw InputError("system.stiffness_matrix", "has no positive eigenvalue (largest " + FormatValue(stiffness_max) +
                                                    "): a system without stiffness has no modes");
  }
  if (k_eig.minCoeff() < -kRigidBodyTolerance * stiffness_max) {
    throw InputError("system.stiffness_matrix", "is not positive semi-definite (smallest eigenvalue " +
                                                    FormatValue(k_eig.minCoeff()) + ", largest " +
                                                    FormatValue(stiffness_max) + ")");
  }
  const int rigid = CountRigid(k_eig);
  double stiffness_min = stiffness_max;
  for (int i = 0; i < k_eig.size(); ++i) {
    if (k_eig[i] > kRigidBodyTolerance * stiffness_max) stiffness_min = std::min(stiffness_min, k_eig[i]);
  }
  if (mass_max > kMaxCondition * mass_min) {
    throw InputError("system.mass_matrix", "is too close to singular: eigenvalues from " + FormatValue(mass_min) +
                                               " to " + FormatValue(mass_max) + " (nsmodal honours a ratio up to " +
                                               FormatValue(kMaxCondition) + ")");
  }
  if (stiffness_max > kMaxCondition * stiffness_min) {
    throw InputError("system.stiffness_matrix", "is too close to singular: eigenvalues from " +
                                                    FormatValue(stiffness_min) + " to " + FormatValue(stiffness_max) +
                                                    " (nsmodal honours a ratio up to " + FormatValue(kMaxCondition) +
                                                    ", and takes eigenvalues below " +
                                                    FormatValue(kRigidBodyTolerance) +
                                                    " of the largest as rigid-body modes)");
  }
  if (model.stiffness.rows() != model.mass.rows()) {
    throw InputError("system.stiffness_matrix", "must have the size of system.mass_matrix (" +
                                                    std::to_string(model.mass.rows()) + ")");
  }
  ValidateContacts(model, stiffness_max);
  // Bounds on the linear frequencies from the extreme eigenvalues (Rayleigh
  // quotients): w_min^2 >= k_min / m_max, w_max^2 <= k_max / m_min.
  const double w_low = std::sqrt(stiffness_min / mass_max), w_high = std::sqrt(stiffness_max / mass_min);
  const int n = model.dofs();
  if (model.damping.size() > 0) {
    const std::string field = "system.damping_matrix";
    if (model.damping.rows() != n || model.damping.cols() != n) {
      throw InputError(field, "must be " + std::to_string(n) + "x" + std::to_string(n) + ", got " +
                                  std::to_string(model.damping.rows()) + "x" + std::to_string(model.damping.cols()));
    }
    const Eigen::VectorXd eig = CheckedEigenvalues(model.damping, field);
    const double lmin = eig.minCoeff(), lmax = eig.maxCoeff();
    // Round-off of a matrix assembled from products (Rayleigh, modal) leaves
    // eigenvalues of order 1e-16 of the largest on either side of zero.
    if (lmin < -1e-12 * std::max(lmax, 0.0)) {
      throw InputError(field, "is not positive semi-definite (smallest eigenvalue " + FormatValue(lmin) +
                                  "): negative damping feeds energy in");
    }
    // Decay rates c / m beyond kMaxFrequencyRatio times the fastest frequency
    // make the flight a stiff problem the integrators do not resolve.
    if (lmax / mass_min > kMaxFrequencyRatio * w_high) {
      throw InputError(field, "has decay rates up to " + FormatValue(lmax / mass_min) + " 1/s, more than " +
                                  FormatValue(kMaxFrequencyRatio) + " times the fastest linear frequency " +
                                  FormatValue(w_high) + " rad/s: rescale the damping");
    }
  }
  const double k_min = stiffness_min;  // (a structured binding cannot be captured in C++17)
  auto check_force = [&](const Eigen::VectorXd& f, const std::string& field) {
    if (f.size() == 0) return;
    if (f.size() != n) {
      throw InputError(field, "must have " + std::to_string(n) + " entries (one per dof), got " +
                                  std::to_string(f.size()));
    }
    for (int i = 0; i < n; ++i) {
      if (!std::isfinite(f[i])) {
        throw InputError(field, "entry " + std::to_string(i + 1) + " must be finite, got " + FormatValue(f[i]));
      }
    }
    // The static response's energy |f|^2 / (2 k_min) within the scales honoured.
    if (!(f.squaredNorm() / (2.0 * k_min) <= kMaxEnergyScale)) {
      throw InputError(field, "gives static energies above " + FormatValue(kMaxEnergyScale) + ": rescale the units");
    }
  };
  check_force(model.forcing.constant, "forcing.constant");
  check_force(model.forcing.amplitude, "forcing.amplitude");
  const double w = model.forcing.frequency;
  if (model.forcing.HasHarmonic() &&
      (!std::isfinite(w) || !(w >= w_low / kMaxFrequencyRatio) || !(w <= w_high * kMaxFrequencyRatio))) {
    throw InputError("forcing.frequency",
                     "must be positive, within " + FormatValue(kMaxFrequencyRatio) +
                         " times the linear frequencies (" + FormatValue(w_low / kMaxFrequencyRatio) + " to " +
                         FormatValue(w_high * kMaxFrequencyRatio) + " rad/s), got " + FormatValue(w));
  }
  return rigid;
}

double MechanicalEnergy(const Model& model, const Eigen::VectorXd& z) {
  const int n = model.dofs();
  return 0.5 * z.tail(n).dot(model.mass * z.tail(n)) + 0.5 * z.head(n).dot(model.stiffness * z.head(n));
}

Eigen::MatrixXd RayleighDamping(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& stiffness, double a, double b) {
  if (!(a >= 0.0) || !std::isfinite(a)) {
    throw InputError("system.rayleigh_damping", "coefficient a (of M) must be >= 0 and finite, got " + FormatValue(a));
  }
  if (!(b >= 0.0) || !std::isfinite(b)) {
    throw InputError("system.rayleigh_damping", "coefficient b (of K) must be >= 0 and finite, got " + FormatValue(b));
  }
  return a * mass + b * stiffness;
}

Eigen::MatrixXd ModalDamping(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& stiffness,
                             const std::vector<double>& ratios) {
  const int n = static_cast<int>(mass.rows());
  if (static_cast<int>(ratios.size()) != n) {
    throw InputError("system.damping_ratios", "must have one entry per linear mode (" + std::to_string(n) +
                                                  "), got " + std::to_string(ratios.size()));
  }
  for (int i = 0; i < n; ++i) {
    if (!(ratios[i] >= 0.0) || !std::isfinite(ratios[i])) {
      throw InputError("system.damping_ratios", "entry " + std::to_string(i + 1) + " must be >= 0 and finite, got " +
                                                    FormatValue(ratios[i]));
    }
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ges(stiffness, mass);
  const Eigen::MatrixXd mphi = mass * ges.eigenvectors();  // M Phi
  Eigen::VectorXd rate(n);
  for (int i = 0; i < n; ++i) rate[i] = 2.0 * ratios[i] * std::sqrt(std::max(ges.eigenvalues()[i], 0.0));
  const Eigen::MatrixXd c = mphi * rate.asDiagonal() * mphi.transpose();
  return 0.5 * (c + c.transpose());
}

}  // namespace nsmodal
