#include "nsmodal/contact.h"

#include <cmath>

#include "nsmodal/error.h"

namespace nsmodal {

ContactModel::ContactModel(const Model& m) : model(m), basis(MakeModalBasis(m)) {
  const int n = m.dofs();
  const Eigen::LDLT<Eigen::MatrixXd> m_ldlt(m.mass);
  minv_k = m_ldlt.solve(m.stiffness);
  minv_d = m_ldlt.solve(m.DampingMatrix());
  minv_f0 = m_ldlt.solve(m.ConstantForce());
  minv_f = m_ldlt.solve(m.ForceAmplitude());
  minv_c = m_ldlt.solve(Eigen::VectorXd::Unit(n, m.contact));
  w_cc = minv_c[m.contact];
}

Eigen::VectorXd ContactModel::FreeAcceleration(double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                                               const Eigen::Ref<const Eigen::VectorXd>& v) const {
  Eigen::VectorXd a = -(minv_k * x);
  if (model.HasDamping()) a.noalias() -= minv_d * v;
  if (model.forcing.HasConstant()) a += minv_f0;
  if (model.forcing.HasHarmonic()) a += std::cos(model.forcing.frequency * t) * minv_f;
  return a;
}

double ContactModel::FreeContactAcceleration(double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                                             const Eigen::Ref<const Eigen::VectorXd>& v) const {
  const int c = model.contact;
  double a = -minv_k.row(c).dot(x) + minv_f0[c] + std::cos(model.forcing.frequency * t) * minv_f[c];
  if (model.HasDamping()) a -= minv_d.row(c).dot(v);
  return a;
}

void ContactModel::ApplyImpact(double e, Eigen::Ref<Eigen::VectorXd> v) const {
  v -= ((1.0 + e) * v[model.contact] / w_cc) * minv_c;
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

StickingFlow::StickingFlow(const ContactModel& cm) : cm_(&cm) {
  const Model& m = cm.model;
  const int n = m.dofs();
  nr_ = n - 1;
  for (int i = 0; i < n; ++i) {
    if (i != m.contact) others_.push_back(i);
  }
  Eigen::MatrixXd z = Eigen::MatrixXd::Zero(n, nr_);
  for (int j = 0; j < nr_; ++j) z(others_[j], j) = 1.0;
  const Eigen::VectorXd ec = Eigen::VectorXd::Unit(n, m.contact);
  const Eigen::RowVectorXd row = cm.minv_k.row(m.contact);
  if (nr_ == 0) {
    a0_ = -row.dot(m.gap * ec);
    return;
  }
  const Eigen::MatrixXd mr = z.transpose() * m.mass * z;
  const Eigen::MatrixXd kr = z.transpose() * m.stiffness * z;
  // Held, the other dofs must not drift: a rigid-body mode that the contact
  // does not hold (a part of the system not tied to the contact dof) would
  // leave K_r singular.
  const int rigid = RigidBodyModes(kr);
  if (rigid > 0) {
    throw InputError("system.stiffness_matrix",
                     "holding the contact dof " + std::to_string(m.contact + 1) + " leaves " +
                         std::to_string(rigid) + " rigid-body mode(s) of the other dofs (a part not tied to it): " +
                         "the sticking phase of such a system is not modelled; tie that part with a spring");
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ges(kr, mr);
  omega_ = ges.eigenvalues().cwiseSqrt();
  phi_ = ges.eigenvectors();
  phi_inv_ = phi_.transpose() * mr;
  xi_star_ = -m.gap * kr.ldlt().solve(z.transpose() * m.stiffness * ec);
  // a_c = -row . (Z (xi* + Phi_r eta) + d e_c) = a0 + rho . eta
  a0_ = -row.dot(z * xi_star_ + m.gap * ec);
  rho_ = -(row * z * phi_).transpose();
}

Eigen::VectorXd StickingFlow::Enter(const Eigen::VectorXd& x, const Eigen::VectorXd& v) const {
  Eigen::VectorXd yr(2 * nr_);
  if (nr_ == 0) return yr;
  Eigen::VectorXd xi(nr_), xid(nr_);
  for (int j = 0; j < nr_; ++j) {
    xi[j] = x[others_[j]];
    xid[j] = v[others_[j]];
  }
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
  Eigen::VectorXd z = Eigen::VectorXd::Zero(2 * n);
  z[cm_->model.contact] = cm_->model.gap;
  if (nr_ == 0) return z;
  const Eigen::VectorXd xi = xi_star_ + phi_ * yr.head(nr_).cwiseQuotient(omega_);
  const Eigen::VectorXd xid = phi_ * yr.tail(nr_);
  for (int j = 0; j < nr_; ++j) {
    z[others_[j]] = xi[j];
    z[n + others_[j]] = xid[j];
  }
  return z;
}

SinusoidSum StickingFlow::ContactAcceleration(const Eigen::VectorXd& yr) const {
  if (nr_ == 0) return SinusoidSum(a0_, Eigen::VectorXd(), Eigen::VectorXd(), Eigen::VectorXd());
  const Eigen::VectorXd r = rho_.cwiseQuotient(omega_);
  return SinusoidSum(a0_, r.cwiseProduct(yr.head(nr_)), r.cwiseProduct(yr.tail(nr_)), omega_);
}

}  // namespace nsmodal

namespace nsmodal {
namespace {

// Z: the dofs other than the contact one, as columns of the identity.
Eigen::MatrixXd Others(int n, int contact) {
  Eigen::MatrixXd z = Eigen::MatrixXd::Zero(n, n - 1);
  for (int i = 0, j = 0; i < n; ++i) {
    if (i != contact) z(i, j++) = 1.0;
  }
  return z;
}

ForcedFlow HeldFlow(const ContactModel& cm) {
  const Model& m = cm.model;
  const int n = m.dofs();
  const Eigen::MatrixXd z = Others(n, m.contact);
  const Eigen::VectorXd ec = Eigen::VectorXd::Unit(n, m.contact);
  const Eigen::VectorXd f0 = m.ConstantForce() - m.gap * (m.stiffness * ec);
  return ForcedFlow(z.transpose() * m.mass * z, z.transpose() * m.DampingMatrix() * z,
                    z.transpose() * m.stiffness * z, z.transpose() * f0, z.transpose() * m.ForceAmplitude(),
                    m.forcing.frequency);
}

}  // namespace

ForcedStickingFlow::ForcedStickingFlow(const ContactModel& cm) : cm_(&cm), flow_(HeldFlow(cm)) {
  const Model& m = cm.model;
  const int n = m.dofs(), c = m.contact;
  for (int i = 0; i < n; ++i) {
    if (i != c) others_.push_back(i);
  }
  const Eigen::MatrixXd z = Others(n, c);
  const Eigen::VectorXd ec = Eigen::VectorXd::Unit(n, c);
  // a_c = row (f0 + f cos(w t) - C Z xi' - K (Z xi + d e_c)), row = e_c' M^-1;
  // the release signal is -a_c.
  const Eigen::RowVectorXd row = cm.minv_c.transpose();  // M^-1 symmetric: its row c is (M^-1 e_c)'
  release_row_.resize(2 * (n - 1));
  release_row_.head(n - 1) = row * m.stiffness * z;
  release_row_.tail(n - 1) = row * m.DampingMatrix() * z;
  release_c0_ = -(cm.minv_f0[c] - m.gap * row.dot(m.stiffness * ec));
  release_c1_ = -cm.minv_f[c];
}

Eigen::VectorXd ForcedStickingFlow::Enter(const Eigen::VectorXd& z) const {
  const int n = cm_->model.dofs(), nr = n - 1;
  Eigen::VectorXd zr(2 * nr);
  for (int j = 0; j < nr; ++j) {
    zr[j] = z[others_[j]];
    zr[nr + j] = z[n + others_[j]];
  }
  return zr;
}

Eigen::VectorXd ForcedStickingFlow::Physical(const Eigen::VectorXd& zr) const {
  const int n = cm_->model.dofs(), nr = n - 1;
  Eigen::VectorXd z = Eigen::VectorXd::Zero(2 * n);
  z[cm_->model.contact] = cm_->model.gap;
  for (int j = 0; j < nr; ++j) {
    z[others_[j]] = zr[j];
    z[n + others_[j]] = zr[nr + j];
  }
  return z;
}

void ForcedStickingFlow::Release(double t, const Eigen::VectorXd& zr, DampedSignal& out) const {
  flow_.Observe(t, zr, release_row_, release_c0_, release_c1_, out);
}

}  // namespace nsmodal
