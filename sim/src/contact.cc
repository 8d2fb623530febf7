#include "nsmodal/contact.h"

#include <algorithm>
#include <cmath>

#include "nsmodal/error.h"

namespace nsmodal {

ContactModel::ContactModel(const Model& m) : model(m), basis(MakeModalBasis(m)) {
  const Eigen::LDLT<Eigen::MatrixXd> m_ldlt(m.mass);
  minv_k = m_ldlt.solve(m.stiffness);
  minv_d = m_ldlt.solve(m.DampingMatrix());
  minv_f0 = m_ldlt.solve(m.ConstantForce());
  minv_f = m_ldlt.solve(m.ForceAmplitude());
  const int k = m.NumContacts();
  for (const Contact& c : m.contacts) {
    ContactTerms t;
    t.minv_n = m_ldlt.solve(c.normal);
    t.w = c.Along(t.minv_n);
    t.k_row = c.RowOf(minv_k);
    t.d_row = c.RowOf(minv_d);
    t.f0 = c.Along(minv_f0);
    t.f = c.Along(minv_f);
    terms.push_back(std::move(t));
  }
  delassus.resize(k, k);
  for (int i = 0; i < k; ++i) {
    for (int j = 0; j < k; ++j) delassus(i, j) = m.contacts[i].Along(terms[j].minv_n);
  }
}

Eigen::VectorXd ContactModel::FreeAcceleration(double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                                               const Eigen::Ref<const Eigen::VectorXd>& v) const {
  Eigen::VectorXd a = -(minv_k * x);
  if (model.HasDamping()) a.noalias() -= minv_d * v;
  if (model.forcing.HasConstant()) a += minv_f0;
  if (model.forcing.HasHarmonic()) a += std::cos(model.forcing.frequency * t) * minv_f;
  return a;
}

double ContactModel::FreeContactAcceleration(int j, double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                                             const Eigen::Ref<const Eigen::VectorXd>& v) const {
  const ContactTerms& c = terms[j];
  double a = -c.k_row.dot(x) + c.f0 + std::cos(model.forcing.frequency * t) * c.f;
  if (model.HasDamping()) a -= c.d_row.dot(v);
  return a;
}

void ContactModel::ApplyImpact(int j, double e, Eigen::Ref<Eigen::VectorXd> v) const {
  const ContactTerms& c = terms[j];
  v -= ((1.0 + e) * model.contacts[j].Along(v) / c.w) * c.minv_n;
}

bool ContactModel::ApplyImpacts(const std::vector<int>& set, Eigen::Ref<Eigen::VectorXd> v, bool plastic,
                                std::vector<int>* struck) const {
  if (struck != nullptr) struck->clear();
  auto e_of = [&](int j) { return plastic ? 0.0 : model.contacts[j].restitution; };
  const int k = static_cast<int>(set.size());
  bool diagonal = true;
  for (int a = 0; a < k && diagonal; ++a) {
    for (int b = 0; b < k; ++b) {
      // Round-off of M^-1 n_j's solve leaves ~1e-16 of the diagonal where G is exactly diagonal.
      if (a != b && std::abs(delassus(set[a], set[b])) >
                        1e-13 * std::sqrt(delassus(set[a], set[a]) * delassus(set[b], set[b]))) {
        diagonal = false;
        break;
      }
    }
  }
  if (diagonal) {
    // Independent: each contact's own law (the normal velocities of the
    // others do not change: n_i . M^-1 n_j = G_ij = 0).
    for (int j : set) {
      if (model.contacts[j].Along(v) > 0.0) {
        ApplyImpact(j, e_of(j), v);
        if (struck != nullptr) struck->push_back(j);
      }
    }
    return true;
  }
  Eigen::VectorXd q(k);
  for (int a = 0; a < k; ++a) q[a] = -(1.0 + e_of(set[a])) * model.contacts[set[a]].Along(v);
  const LcpSolution p = SolveLcp(DelassusBlock(set), q);
  if (!p.solved) return false;
  for (int a = 0; a < k; ++a) {
    if (!(p.z[a] > 0.0)) continue;
    v -= p.z[a] * terms[set[a]].minv_n;
    if (struck != nullptr) struck->push_back(set[a]);
  }
  return true;
}

bool ContactModel::HoldVelocity(const std::vector<int>& set, Eigen::Ref<Eigen::VectorXd> v) const {
  const int k = static_cast<int>(set.size());
  Eigen::VectorXd u(k);
  for (int a = 0; a < k; ++a) u[a] = model.contacts[set[a]].Along(v);
  const Eigen::LDLT<Eigen::MatrixXd> g(DelassusBlock(set));
  if (g.info() != Eigen::Success || !(g.rcond() > 1e-12)) return false;
  const Eigen::VectorXd p = g.solve(u);
  for (int a = 0; a < k; ++a) v -= p[a] * terms[set[a]].minv_n;
  return true;
}

bool ContactModel::HeldByForces(const std::vector<int>& set, double t, const Eigen::Ref<const Eigen::VectorXd>& z,
                                std::vector<int>& held) const {
  const int n = model.dofs(), k = static_cast<int>(set.size());
  const Eigen::VectorXd a = FreeAcceleration(t, z.head(n), z.tail(n));
  Eigen::VectorXd q(k);
  for (int i = 0; i < k; ++i) q[i] = -model.contacts[set[i]].Along(a);
  const LcpSolution lambda = SolveLcp(DelassusBlock(set), q);
  if (!lambda.solved) return false;
  held.clear();
  for (int i = 0; i < k; ++i) {
    if (lambda.z[i] > 0.0) held.push_back(set[i]);
  }
  return true;
}

Eigen::MatrixXd ContactModel::DelassusBlock(const std::vector<int>& set) const {
  const int k = static_cast<int>(set.size());
  Eigen::MatrixXd g(k, k);
  for (int a = 0; a < k; ++a) {
    for (int b = 0; b < k; ++b) g(a, b) = delassus(set[a], set[b]);
  }
  return g;
}

double ContactModel::MaxDelassus() const {
  double w = 0.0;
  for (const ContactTerms& t : terms) w = std::max(w, t.w);
  return w;
}

double ContactModel::EnergyScale(const Eigen::VectorXd& x0, const Eigen::VectorXd& v0) const {
  double e = EnergyOf(x0, v0);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.dofs());
  if (model.forcing.HasConstant()) e += EnergyOf(model.stiffness.ldlt().solve(model.forcing.constant), zero);
  if (model.forcing.HasHarmonic()) {
    const double w = model.forcing.frequency;
    // At an undamped resonance (no bounded steady state) the static response
    // to f stands for it.
    const Eigen::VectorXcd x =
        HarmonicResponse(model.mass, model.damping, model.stiffness, model.forcing.amplitude, w)
            .value_or(model.stiffness.ldlt().solve(model.forcing.amplitude).cast<std::complex<double>>());
    e += EnergyOf(x.real(), w * x.imag()) + EnergyOf(x.imag(), w * x.real());
  }
  return e;
}

ContactDecision DecideContact(double vc, double ac, double e, const ContactResolution& r) {
  if (vc <= r.vtol) return {ac > 0.0 ? ContactOutcome::kHold : ContactOutcome::kGraze};
  const double vplus = e * vc;
  if (e > 0.0 && e < 1.0 && ac > 0.0 &&
      (vplus <= r.vtol || vplus * vplus / (2.0 * ac) <= r.height || 2.0 * vplus / ac < r.zeno_flight)) {
    return {ContactOutcome::kImpactZeno, 2.0 * vplus / (ac * (1.0 - e))};
  }
  if (vplus <= r.vtol && ac > 0.0) return {ContactOutcome::kImpactHold};
  return {ContactOutcome::kImpact};
}

HeldSpace::HeldSpace(const ContactModel& cm, std::vector<int> held) : set(std::move(held)) {
  std::sort(set.begin(), set.end());
  const int n = cm.model.dofs(), k = static_cast<int>(set.size());
  bool dof_stops = true;
  std::vector<bool> taken(n, false);
  for (int j : set) {
    const Contact& c = cm.contact(j);
    normals.push_back(c.normal);
    dof_stops = dof_stops && c.form == Contact::Form::kDof && !taken[c.dof];
    if (c.form == Contact::Form::kDof) taken[c.dof] = true;
  }
  if (k == 1) {
    coefficients = {cm.contact(set[0]).gap / normals[0].squaredNorm()};
  } else {
    Eigen::MatrixXd hh(k, k);
    Eigen::VectorXd d(k);
    for (int a = 0; a < k; ++a) {
      d[a] = cm.contact(set[a]).gap;
      for (int b = 0; b < k; ++b) hh(a, b) = normals[a].dot(normals[b]);
    }
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(hh);
    if (lu.rank() < k) {
      throw InputError("contact", "the held contacts have dependent normals: holding them together is not modelled");
    }
    const Eigen::VectorXd c = lu.solve(d);
    coefficients.assign(c.data(), c.data() + k);
  }
  if (dof_stops) {
    // The other dofs' unit vectors: held coordinates are those dofs' own.
    z = Eigen::MatrixXd::Zero(n, n - k);
    for (int i = 0, col = 0; i < n; ++i) {
      if (!taken[i]) {
        others.push_back(i);
        z(i, col++) = 1.0;
      }
    }
    return;
  }
  // An orthonormal complement of the normals: the last N - |S| columns of
  // the Householder Q of H'.
  Eigen::MatrixXd ht(n, k);
  for (int a = 0; a < k; ++a) ht.col(a) = normals[a];
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(ht);
  z = Eigen::MatrixXd(qr.householderQ()).rightCols(n - k);
}

Eigen::VectorXd HeldSpace::Particular() const {
  Eigen::VectorXd x = coefficients[0] * normals[0];
  for (std::size_t a = 1; a < normals.size(); ++a) x += coefficients[a] * normals[a];
  return x;
}

Eigen::VectorXd HeldSpace::Times(const Eigen::MatrixXd& a) const {
  Eigen::VectorXd out = coefficients[0] * (a * normals[0]);
  for (std::size_t i = 1; i < normals.size(); ++i) out += coefficients[i] * (a * normals[i]);
  return out;
}

double HeldSpace::RowTimes(const Eigen::RowVectorXd& row, const Eigen::MatrixXd& a) const {
  double out = coefficients[0] * row.dot(a * normals[0]);
  for (std::size_t i = 1; i < normals.size(); ++i) out += coefficients[i] * row.dot(a * normals[i]);
  return out;
}

Eigen::VectorXd HeldSpace::Reduce(const Eigen::Ref<const Eigen::VectorXd>& y, bool position) const {
  const int nr = Reduced();
  Eigen::VectorXd out(nr);
  if (!others.empty() || nr == 0) {
    for (int j = 0; j < nr; ++j) out[j] = y[others[j]];
    return out;
  }
  return position ? Eigen::VectorXd(z.transpose() * (y - Particular())) : Eigen::VectorXd(z.transpose() * y);
}

Eigen::VectorXd HeldSpace::Expand(const Eigen::Ref<const Eigen::VectorXd>& xi, bool position) const {
  const int n = static_cast<int>(z.rows());
  if (!others.empty() || Reduced() == 0) {
    Eigen::VectorXd out = position ? Particular() : Eigen::VectorXd::Zero(n);
    for (std::size_t j = 0; j < others.size(); ++j) out[others[j]] = xi[j];
    return out;
  }
  return position ? Eigen::VectorXd(Particular() + z * xi) : Eigen::VectorXd(z * xi);
}

Eigen::MatrixXd HeldForceRows(const ContactModel& cm, const std::vector<int>& set) {
  const int k = static_cast<int>(set.size()), n = cm.model.dofs();
  Eigen::MatrixXd rows(k, n);
  for (int a = 0; a < k; ++a) rows.row(a) = cm.terms[set[a]].minv_n.transpose();  // n_j' M^-1 (M^-1 symmetric)
  if (k == 1) return rows;
  return cm.DelassusBlock(set).ldlt().solve(rows);
}

StickingFlow::StickingFlow(const ContactModel& cm, std::vector<int> held)
    : cm_(&cm), space_(cm, std::move(held)) {
  const Model& m = cm.model;
  nr_ = space_.Reduced();
  const int k = static_cast<int>(space_.set.size());
  const Eigen::MatrixXd& z = space_.z;
  // Each held contact's force row against x: row_i M^-1 K (for one contact
  // n_j' M^-1 K, the k_row of the one-contact flow).
  Eigen::MatrixXd force_k(k, m.dofs());
  if (k == 1) {
    force_k.row(0) = cm.terms[space_.set[0]].k_row;
  } else {
    force_k = HeldForceRows(cm, space_.set) * m.stiffness;
  }
  a0_.resize(k);
  if (nr_ == 0) {
    for (int i = 0; i < k; ++i) a0_[i] = -force_k.row(i).dot(space_.Particular());
    return;
  }
  const Eigen::MatrixXd mr = z.transpose() * m.mass * z;
  const Eigen::MatrixXd kr = z.transpose() * m.stiffness * z;
  // Held, the other dofs must not drift: a rigid-body mode that the held
  // contacts do not hold (a part of the system not tied to them) would
  // leave K_r singular.
  const int rigid = RigidBodyModes(kr);
  if (rigid > 0) {
    std::string which;
    for (int j : space_.set) which += (which.empty() ? "" : ", ") + std::to_string(j + 1) + " (" + cm.contact(j).Describe() + ")";
    throw InputError("system.stiffness_matrix",
                     "holding contact " + which + " leaves " + std::to_string(rigid) +
                         " rigid-body mode(s) of the other directions (a part not tied to it): " +
                         "the sticking phase of such a system is not modelled; tie that part with a spring");
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ges(kr, mr);
  omega_ = ges.eigenvalues().cwiseSqrt();
  phi_ = ges.eigenvectors();
  phi_inv_ = phi_.transpose() * mr;
  const Eigen::LDLT<Eigen::MatrixXd> kr_ldlt(kr);
  xi_star_ = -space_.coefficients[0] * kr_ldlt.solve(z.transpose() * m.stiffness * space_.normals[0]);
  for (int i = 1; i < k; ++i) {
    xi_star_ -= space_.coefficients[i] * kr_ldlt.solve(z.transpose() * m.stiffness * space_.normals[i]);
  }
  // force_i = -row_i . (Z (xi* + Phi_r eta) + x_p) = a0_i + rho_i . eta
  rho_.resize(nr_, k);
  for (int i = 0; i < k; ++i) {
    const Eigen::RowVectorXd row = force_k.row(i);
    a0_[i] = -row.dot(z * xi_star_ + space_.Particular());
    rho_.col(i) = -(row * z * phi_).transpose();
  }
}

Eigen::VectorXd StickingFlow::Enter(const Eigen::VectorXd& x, const Eigen::VectorXd& v) const {
  Eigen::VectorXd yr(2 * nr_);
  if (nr_ == 0) return yr;
  const Eigen::VectorXd xi = space_.Reduce(x, true), xid = space_.Reduce(v, false);
  yr.head(nr_) = omega_.cwiseProduct(phi_inv_ * (xi - xi_star_));
  yr.tail(nr_) = phi_inv_ * xid;
  return yr;
}

void StickingFlow::Advance(double dt, Eigen::Ref<Eigen::VectorXd> yr) const {
  for (int i = 0; i < nr_; ++i) {
    const double c = std::cos(omega_[i] * dt), s = std::sin(omega_[i] * dt);
    const double u = yr[i], w = yr[nr_ + i];
    yr[i] = c * u + s * w;
    yr[nr_ + i] = -s * u + c * w;
  }
}

Eigen::VectorXd StickingFlow::Physical(const Eigen::VectorXd& yr) const {
  const int n = cm_->model.dofs();
  Eigen::VectorXd z(2 * n);
  if (nr_ == 0) {
    z << space_.Particular(), Eigen::VectorXd::Zero(n);
    return z;
  }
  z << space_.Expand(xi_star_ + phi_ * yr.head(nr_).cwiseQuotient(omega_), true),
      space_.Expand(phi_ * yr.tail(nr_), false);
  return z;
}

SinusoidSum StickingFlow::ContactAcceleration(int i, const Eigen::VectorXd& yr) const {
  if (nr_ == 0) return SinusoidSum(a0_[i], Eigen::VectorXd(), Eigen::VectorXd(), Eigen::VectorXd());
  const Eigen::VectorXd r = rho_.col(i).cwiseQuotient(omega_);
  return SinusoidSum(a0_[i], r.cwiseProduct(yr.head(nr_)), r.cwiseProduct(yr.tail(nr_)), omega_);
}

SinusoidSum StickingFlow::OtherGap(int k, const Eigen::VectorXd& yr) const {
  const Contact& c = cm_->contact(k);
  const double c0 = c.Along(space_.Particular()) - c.gap;
  if (nr_ == 0) return SinusoidSum(c0, Eigen::VectorXd(), Eigen::VectorXd(), Eigen::VectorXd());
  // n_k . x = n_k . (x_p + Z xi*) + (n_k' Z Phi_r) (u / w)
  const Eigen::RowVectorXd nz = c.normal.transpose() * space_.z;
  const Eigen::VectorXd g = (nz * phi_).transpose().cwiseQuotient(omega_);
  return SinusoidSum(c0 + nz.dot(xi_star_), g.cwiseProduct(yr.head(nr_)), g.cwiseProduct(yr.tail(nr_)), omega_);
}

}  // namespace nsmodal

namespace nsmodal {
namespace {

ForcedFlow HeldFlow(const ContactModel& cm, const HeldSpace& space) {
  const Model& m = cm.model;
  const Eigen::MatrixXd& z = space.z;
  const Eigen::VectorXd f0 = m.ConstantForce() - space.Times(m.stiffness);
  return ForcedFlow(z.transpose() * m.mass * z, z.transpose() * m.DampingMatrix() * z,
                    z.transpose() * m.stiffness * z, z.transpose() * f0, z.transpose() * m.ForceAmplitude(),
                    m.forcing.frequency);
}

}  // namespace

ForcedStickingFlow::ForcedStickingFlow(const ContactModel& cm, std::vector<int> held)
    : cm_(&cm), space_(cm, std::move(held)), flow_(HeldFlow(cm, space_)) {
  const Model& m = cm.model;
  const int nr = space_.Reduced();
  const Eigen::MatrixXd& z = space_.z;
  // force_i = row_i (f0 + f cos(w t) - C Z xi' - K (Z xi + x_p)) (HeldForceRows;
  // one contact: row = n_j' M^-1); the release signal is -force_i.
  const Eigen::MatrixXd rows = HeldForceRows(cm, space_.set);
  for (int i = 0; i < static_cast<int>(space_.set.size()); ++i) {
    const Eigen::RowVectorXd row = rows.row(i);
    Eigen::RowVectorXd r(2 * nr);
    r.head(nr) = row * m.stiffness * z;
    r.tail(nr) = row * m.DampingMatrix() * z;
    release_rows_.push_back(r);
    // One contact: n_j . M^-1 f0 and n_j . M^-1 f as the one-contact flow had them.
    const bool one = space_.set.size() == 1;
    const ContactTerms& t = cm.terms[space_.set[0]];
    release_c0_.push_back(-((one ? t.f0 : row.dot(m.ConstantForce())) - space_.RowTimes(row, m.stiffness)));
    release_c1_.push_back(-(one ? t.f : row.dot(m.ForceAmplitude())));
  }
}

Eigen::VectorXd ForcedStickingFlow::Enter(const Eigen::VectorXd& z) const {
  const int n = cm_->model.dofs(), nr = space_.Reduced();
  Eigen::VectorXd zr(2 * nr);
  zr << space_.Reduce(z.head(n), true), space_.Reduce(z.tail(n), false);
  return zr;
}

Eigen::VectorXd ForcedStickingFlow::Physical(const Eigen::VectorXd& zr) const {
  const int n = cm_->model.dofs(), nr = space_.Reduced();
  Eigen::VectorXd z(2 * n);
  z << space_.Expand(zr.head(nr), true), space_.Expand(zr.tail(nr), false);
  return z;
}

void ForcedStickingFlow::Release(int i, double t, const Eigen::VectorXd& zr, DampedSignal& out) const {
  flow_.Observe(t, zr, release_rows_[i], release_c0_[i], release_c1_[i], out);
}

void ForcedStickingFlow::OtherGap(int k, double t, const Eigen::VectorXd& zr, DampedSignal& out) const {
  const Contact& c = cm_->contact(k);
  const int nr = space_.Reduced();
  Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(2 * nr);
  row.head(nr) = c.normal.transpose() * space_.z;
  flow_.Observe(t, zr, row, c.Along(space_.Particular()) - c.gap, 0.0, out);
}

}  // namespace nsmodal
