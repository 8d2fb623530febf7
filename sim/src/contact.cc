#include "nsmodal/contact.h"

#include <cmath>

namespace nsmodal {

ContactModel::ContactModel(const Model& m) : model(m), basis(MakeModalBasis(m)) {
  minv_k = m.mass.ldlt().solve(m.stiffness);
  minv_c = m.mass.ldlt().solve(Eigen::VectorXd::Unit(m.dofs(), m.contact));
  w_cc = minv_c[m.contact];
}

void ContactModel::ApplyImpact(double e, Eigen::Ref<Eigen::VectorXd> v) const {
  v -= ((1.0 + e) * v[model.contact] / w_cc) * minv_c;
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
