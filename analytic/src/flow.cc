#include "nsmodal/flow.h"

#include <cmath>

namespace nsmodal {

void Flow(const ModalBasis& b, double t, Eigen::Ref<Eigen::VectorXd> y) {
  for (int i = 0; i < b.rigid; ++i) y[i] += t * y[b.n + i];  // free drift, u_i = q_i
  for (int i = b.rigid; i < b.n; ++i) {
    const double c = std::cos(b.omega[i] * t);
    const double s = std::sin(b.omega[i] * t);
    const double u = y[i];
    const double w = y[b.n + i];
    y[i] = c * u + s * w;
    y[b.n + i] = -s * u + c * w;
  }
}

void Impact(const ModalBasis& b, double e, Eigen::Ref<Eigen::VectorXd> y) {
  const double vc = b.r.dot(y.tail(b.n));
  y.tail(b.n) -= ((1.0 + e) * vc / b.r_norm2) * b.r;
}

Eigen::MatrixXd FlowMatrix(const ModalBasis& b, double t) {
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(2 * b.n, 2 * b.n);
  for (int i = 0; i < b.rigid; ++i) {
    s(i, i) = s(b.n + i, b.n + i) = 1.0;
    s(i, b.n + i) = t;
  }
  for (int i = b.rigid; i < b.n; ++i) {
    const double c = std::cos(b.omega[i] * t);
    const double sn = std::sin(b.omega[i] * t);
    s(i, i) = c;
    s(i, b.n + i) = sn;
    s(b.n + i, i) = -sn;
    s(b.n + i, b.n + i) = c;
  }
  return s;
}

Eigen::MatrixXd ImpactMatrix(const ModalBasis& b, double e) {
  Eigen::MatrixXd m = Eigen::MatrixXd::Identity(2 * b.n, 2 * b.n);
  m.bottomRightCorner(b.n, b.n) -= ((1.0 + e) / b.r_norm2) * b.r * b.r.transpose();
  return m;
}

SinusoidSum::SinusoidSum(double c, Eigen::VectorXd a_in, Eigen::VectorXd b_in, Eigen::VectorXd omega_in)
    : offset(c), a(std::move(a_in)), b(std::move(b_in)), omega(std::move(omega_in)) {
  UpdateBounds();
}

void SinusoidSum::UpdateBounds() {
  for (double& v : bound) v = 0.0;
  for (int i = 0; i < omega.size(); ++i) {
    const double amp = std::hypot(a[i], b[i]);
    double wk = 1.0;
    for (int k = 0; k < 5; ++k) {
      bound[k] += wk * amp;
      wk *= omega[i];
    }
  }
  bound[1] += std::abs(slope);
}

ContactSignal::ContactSignal(const ModalBasis& basis, const Eigen::Ref<const Eigen::VectorXd>& y) {
  omega = basis.omega;
  Reset(basis, y);
}

void ContactSignal::Reset(const ModalBasis& basis, const Eigen::Ref<const Eigen::VectorXd>& y) {
  a = basis.r_over_omega.cwiseProduct(y.head(basis.n));
  b = basis.r_over_omega.cwiseProduct(y.tail(basis.n));
  // A rigid-body mode (w_i = 0) drifts: its a_i = r_i q_i stays (cos 0 = 1),
  // its velocity term is the slope r_i s_i, not b_i sin(0).
  const int rigid = basis.rigid;
  slope = b.head(rigid).sum();
  b.head(rigid).setZero();
  UpdateBounds();
}

double SinusoidSum::Position(double t) const {
  double f = offset + slope * t;
  for (int i = 0; i < omega.size(); ++i) f += a[i] * std::cos(omega[i] * t) + b[i] * std::sin(omega[i] * t);
  return f;
}

double SinusoidSum::Velocity(double t) const {
  double f = slope;
  for (int i = 0; i < omega.size(); ++i) {
    f += omega[i] * (b[i] * std::cos(omega[i] * t) - a[i] * std::sin(omega[i] * t));
  }
  return f;
}

double SinusoidSum::Acceleration(double t) const {
  double f = 0.0;
  for (int i = 0; i < omega.size(); ++i) {
    f -= omega[i] * omega[i] * (a[i] * std::cos(omega[i] * t) + b[i] * std::sin(omega[i] * t));
  }
  return f;
}

std::pair<double, double> SinusoidSum::VelocityAcceleration(double t) const {
  double v = slope, acc = 0.0;
  for (int i = 0; i < omega.size(); ++i) {
    const double c = std::cos(omega[i] * t), s = std::sin(omega[i] * t);
    v += omega[i] * (b[i] * c - a[i] * s);
    acc -= omega[i] * omega[i] * (a[i] * c + b[i] * s);
  }
  return {v, acc};
}

void SinusoidSum::Derivatives(double t, double out[4]) const {
  out[0] = offset + slope * t;
  out[1] = slope;
  out[2] = out[3] = 0.0;
  for (int i = 0; i < omega.size(); ++i) {
    const double c = std::cos(omega[i] * t), s = std::sin(omega[i] * t), w = omega[i];
    const double p = a[i] * c + b[i] * s;  // the term itself
    const double q = b[i] * c - a[i] * s;  // its derivative divided by w
    out[0] += p;
    out[1] += w * q;
    out[2] -= w * w * p;
    out[3] -= w * w * w * q;
  }
}

}  // namespace nsmodal
