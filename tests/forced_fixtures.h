#pragma once
// Independent evaluations of the damped, forced model (model.h), shared by
// the flight and the simulator tests: none of them calls forced_flow.h.
#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <utility>

#include "nsmodal/modal_basis.h"
#include "nsmodal/model.h"

namespace nsmodal::testing {

// The steady state the receptance gives:
// x_p(t) = K^-1 f0 + Re[(K - w^2 M + i w C)^-1 f e^{i w t}], v_p = x_p'.
inline Eigen::VectorXd ReceptanceState(const Model& m, double t) {
  using Complex = std::complex<double>;
  const double w = m.forcing.frequency;
  const Eigen::MatrixXcd dyn = m.stiffness.cast<Complex>() - w * w * m.mass.cast<Complex>() +
                               Complex(0.0, w) * m.DampingMatrix().cast<Complex>();
  const Eigen::VectorXcd x = dyn.fullPivLu().solve(m.ForceAmplitude().cast<Complex>());
  const Complex e = std::polar(1.0, w * t);
  Eigen::VectorXd z(2 * m.dofs());
  z << m.stiffness.fullPivLu().solve(m.ConstantForce()) + (x * e).real(), (x * (Complex(0.0, w) * e)).real();
  return z;
}

// The paper's chain, e = 0.8, Rayleigh damping C = 0.05 M + 0.02 K, a
// harmonic force at w = 0.5 mostly on m1 and a small preload. From
// x = (0.2, -0.1), v = (0, 0.3) it settles on a stable response with one
// impact per forcing period.
inline Model DampedForcedPaper() {
  Model m = PaperModel();
  m.FirstContact().restitution = 0.8;
  m.damping = RayleighDamping(m.mass, m.stiffness, 0.05, 0.02);
  m.forcing.amplitude = Eigen::Vector2d(0.3, 0.1);
  m.forcing.constant = Eigen::Vector2d(0.05, -0.02);
  m.forcing.frequency = 0.5;
  return m;
}

// configs/forced.toml: the paper's system, 2 % modal damping, e = 0.8, a
// force on m1 at w = 0.5.
inline Model ForcedScene() {
  Model m = PaperModel();
  m.FirstContact().restitution = 0.8;
  m.damping = ModalDamping(m.mass, m.stiffness, {0.02, 0.02});
  m.forcing.amplitude = Eigen::Vector2d(0.3, 0.0);
  m.forcing.frequency = 0.5;
  return m;
}

// An event-driven evaluation written apart from the library: each mode of a
// proportionally damped model is the textbook damped oscillator
//   q'' + 2 zeta w q' + w^2 q = phi' (f0 + f cos(W t)),
//   q(t0 + s) = q_p(t0 + s) + e^{-zeta w s} (A cos(w_d s) + B sin(w_d s)),
// impacts are found by sampling x_c every h and bisecting the first sample
// past d to the last bit, and the impact law is applied in physical
// coordinates. It needs every impact to rise through d faster than the
// sampling can miss, which the scene below does (its impact velocities
// exceed 0.1).
class TextbookSimulator {
 public:
  explicit TextbookSimulator(const Model& m) : m_(m), b_(MakeModalBasis(m)) {
    const Eigen::MatrixXd modal = b_.phi.transpose() * m.DampingMatrix() * b_.phi;
    zeta_ = modal.diagonal().cwiseQuotient(2.0 * b_.omega);
    f0_ = b_.phi.transpose() * m.ConstantForce();
    f_ = b_.phi.transpose() * m.ForceAmplitude();
    minv_c_ = m.mass.inverse().col(m.FirstContact().dof);
  }
  // Modal coordinate i's particular solution and its derivative at t.
  std::pair<double, double> Particular(int i, double t) const {
    using Complex = std::complex<double>;
    const double w = b_.omega[i], W = m_.forcing.frequency;
    const Complex h = f_[i] / Complex(w * w - W * W, 2.0 * zeta_[i] * w * W);
    const Complex e = std::polar(1.0, W * t);
    return {f0_[i] / (w * w) + (h * e).real(), (Complex(0.0, W) * h * e).real()};
  }
  // (q, q') of every mode at t0 + s from (q, q') at t0.
  Eigen::VectorXd Flight(const Eigen::VectorXd& qq, double t0, double s) const {
    const int n = b_.n;
    Eigen::VectorXd out(2 * n);
    for (int i = 0; i < n; ++i) {
      const double w = b_.omega[i], z = zeta_[i], wd = w * std::sqrt(1.0 - z * z);
      const auto [p0, dp0] = Particular(i, t0);
      const auto [p1, dp1] = Particular(i, t0 + s);
      const double a = qq[i] - p0, bb = (qq[n + i] - dp0 + z * w * a) / wd;
      const double decay = std::exp(-z * w * s), c = std::cos(wd * s), sn = std::sin(wd * s);
      out[i] = p1 + decay * (a * c + bb * sn);
      out[n + i] = dp1 + decay * (-z * w * (a * c + bb * sn) + wd * (-a * sn + bb * c));
    }
    return out;
  }
  double Gap(const Eigen::VectorXd& qq) const { return b_.r.dot(qq.head(b_.n)) - m_.FirstContact().gap; }

  // The physical state at t_end from (x0, v0); counts impacts.
  Eigen::VectorXd Run(const Eigen::VectorXd& x0, const Eigen::VectorXd& v0, double t_end, long* impacts) const {
    const int n = b_.n;
    Eigen::VectorXd qq(2 * n);
    qq << b_.phi_inv * x0, b_.phi_inv * v0;
    double t = 0.0;
    const double h = 0.005;
    *impacts = 0;
    while (true) {
      double s = h;
      while (t + s < t_end && Gap(Flight(qq, t, s)) < 0.0) s += h;
      if (t + s >= t_end) {
        qq = Flight(qq, t, t_end - t);
        break;
      }
      double lo = s - h, hi = s;
      for (int k = 0; k < 80 && hi - lo > 0.0; ++k) {
        const double mid = 0.5 * (lo + hi);
        if (mid == lo || mid == hi) break;
        (Gap(Flight(qq, t, mid)) < 0.0 ? lo : hi) = mid;
      }
      qq = Flight(qq, t, hi);
      t += hi;
      Eigen::VectorXd v = b_.phi * qq.tail(n);
      v -= (1.0 + m_.FirstContact().restitution) * v[m_.FirstContact().dof] / minv_c_[m_.FirstContact().dof] * minv_c_;
      qq.tail(n) = b_.phi_inv * v;
      ++*impacts;
    }
    Eigen::VectorXd z(2 * n);
    z << b_.phi * qq.head(n), b_.phi * qq.tail(n);
    return z;
  }

 private:
  Model m_;
  ModalBasis b_;
  Eigen::VectorXd zeta_, f0_, f_, minv_c_;
};

}  // namespace nsmodal::testing
