#include "nsmodal/forced_flow.h"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "nsmodal/check.h"
#include "nsmodal/error.h"

namespace nsmodal {

void DampedSignal::UpdateBounds() {
  for (double& b : bound) b = 0.0;
  for (int j = 0; j < beta.size(); ++j) {
    const double amp = std::abs(beta[j]), rate = std::abs(mu[j]);
    double rk = 1.0;
    for (double& b : bound) {
      b += amp * rk;
      rk *= rate;
    }
  }
  bound[1] += std::abs(slope);
}

double DampedSignal::Position(double s) const {
  double out[4];
  Derivatives(s, out);
  return out[0];
}

double DampedSignal::Velocity(double s) const {
  double out[4];
  Derivatives(s, out);
  return out[1];
}

double DampedSignal::Acceleration(double s) const {
  double out[4];
  Derivatives(s, out);
  return out[2];
}

void DampedSignal::Derivatives(double s, double out[4]) const {
  out[0] = offset + slope * s;
  out[1] = slope;
  out[2] = out[3] = 0.0;
  for (int j = 0; j < beta.size(); ++j) {
    std::complex<double> term = beta[j] * std::exp(mu[j] * s);
    for (int k = 0; k < 4; ++k) {
      out[k] += term.real();
      term *= mu[j];
    }
  }
}

double DampedSignal::MaxRate() const {
  double r = 0.0;
  for (int j = 0; j < mu.size(); ++j) r = std::max(r, std::abs(mu[j]));
  return r > 0.0 ? r : 1.0;
}

RigidBodySplit SplitRigidBody(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& damping,
                              const Eigen::MatrixXd& stiffness, const Eigen::VectorXd& constant_force, int rigid) {
  const int n = static_cast<int>(mass.rows());
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ges(stiffness, mass);
  NSMODAL_CHECK(ges.info() == Eigen::Success);
  RigidBodySplit out{ges.eigenvectors().leftCols(rigid), ges.eigenvectors().rightCols(n - rigid),
                     ges.eigenvalues().tail(n - rigid)};
  // Round-off leaves C Phi_0 and Phi_0' f0 at ~1e-16 of their scales (modal
  // damping gives a rigid mode the rate 0); 1e-12 of the scale is a real
  // dashpot or force.
  const double phi_scale = std::max(1.0, out.rigid.cwiseAbs().maxCoeff());
  const std::string alternative = " in its closed-form flight (the exact integrator, the forced analysis); ";
  // Refuses `what` = size above 1e-12 of `scale`.
  auto refuse_above = [&](double size, double scale, const std::string& field, const std::string& what,
                          const std::string& remedy) {
    if (size > 1e-12 * scale * phi_scale) {
      throw InputError(field, what + " = " + FormatValue(size) + ", not 0: nsmodal flies a rigid-body mode as a free "
                                     "drift" + alternative + remedy + ", or simulate with cvode or moreau-jean");
    }
  };
  if (damping.size() > 0 && rigid > 0) {
    refuse_above((damping * out.rigid).cwiseAbs().maxCoeff(), damping.cwiseAbs().maxCoeff(), "system.damping_matrix",
                 "damps a rigid-body motion: |C Phi_0|", "damp the relative motion only (a dashpot between masses, "
                 "not to ground)");
  }
  if (constant_force.size() > 0 && rigid > 0) {
    refuse_above((out.rigid.transpose() * constant_force).cwiseAbs().maxCoeff(), constant_force.cwiseAbs().maxCoeff(),
                 "forcing.constant", "pushes a rigid-body mode: |Phi_0' f0|",
                 "give a constant force the springs hold (one pushing the free part accelerates it without bound)");
  }
  return out;
}

std::optional<Eigen::VectorXcd> HarmonicResponse(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& damping,
                                                 const Eigen::MatrixXd& stiffness, const Eigen::VectorXd& force,
                                                 double frequency) {
  using Complex = std::complex<double>;
  const double w = frequency;
  Eigen::MatrixXcd dyn = stiffness.cast<Complex>() - (w * w) * mass.cast<Complex>();
  if (damping.size() > 0) dyn += Complex(0.0, w) * damping.cast<Complex>();
  const Eigen::PartialPivLU<Eigen::MatrixXcd> lu(dyn);
  if (!(lu.rcond() > kMinResonanceCondition)) return std::nullopt;
  return Eigen::VectorXcd(lu.solve(force.cast<Complex>()));
}

ForcedFlow::ForcedFlow(const Model& model)
    : ForcedFlow(model.mass, model.damping, model.stiffness, model.forcing.constant, model.forcing.amplitude,
                 model.forcing.frequency) {}

ForcedFlow::ForcedFlow(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& damping, const Eigen::MatrixXd& stiffness,
                       const Eigen::VectorXd& constant_force, const Eigen::VectorXd& force_amplitude, double frequency)
    : n_(static_cast<int>(mass.rows())), w_(frequency) {
  const int n = n_;
  NSMODAL_CHECK(stiffness.rows() == n && stiffness.cols() == n && mass.cols() == n);
  NSMODAL_CHECK(damping.size() == 0 || (damping.rows() == n && damping.cols() == n));
  NSMODAL_CHECK(constant_force.size() == 0 || constant_force.size() == n);
  NSMODAL_CHECK(force_amplitude.size() == 0 || force_amplitude.size() == n);
  const Eigen::MatrixXd c = damping.size() > 0 ? damping : Eigen::MatrixXd::Zero(n, n);
  const bool damped = n > 0 && c.cwiseAbs().maxCoeff() > 0.0;
  x_static_ = Eigen::VectorXd::Zero(n);
  x_harmonic_ = Eigen::VectorXcd::Zero(n);
  if (n == 0) return;
  // The modes of (K, M), M-orthonormal, the rigid-body ones first, when K has
  // any; then the flight's first-order modes are those of the elastic part.
  const int rigid = RigidBodyModes(stiffness);
  Eigen::MatrixXd elastic;  // Phi_e (n x (n - r)), with rigid modes only
  Eigen::VectorXd omega2;   // its K eigenvalues
  if (rigid > 0) {
    RigidBodySplit split = SplitRigidBody(mass, c, stiffness, constant_force, rigid);
    rigid_ = std::move(split.rigid);
    rigid_coord_ = rigid_.transpose() * mass;
    elastic = std::move(split.elastic);
    omega2 = std::move(split.omega2);
    if (constant_force.size() > 0) x_static_ = elastic * (elastic.transpose() * constant_force).cwiseQuotient(omega2);
  } else if (constant_force.size() > 0) {
    x_static_ = Eigen::LDLT<Eigen::MatrixXd>(stiffness).solve(constant_force);
  }
  if (force_amplitude.size() > 0 && force_amplitude.cwiseAbs().maxCoeff() > 0.0) {
    const std::optional<Eigen::VectorXcd> x = HarmonicResponse(mass, c, stiffness, force_amplitude, w_);
    if (!x) {
      throw InputError("forcing.frequency", "w = " + FormatValue(w_) +
                                                " resonates with an undamped linear mode (K - w^2 M + i w C is "
                                                "singular): the closed-form flight has no bounded steady state; "
                                                "add damping or move w");
    }
    x_harmonic_ = *x;
  }
  // The first-order matrix and its modes: of the whole system, or (rigid
  // modes) of the elastic coordinates q_e = Phi_e' M x, whose matrix is
  // [[0, I], [-Omega^2, -Phi_e' C Phi_e]], mapped back by Phi_e.
  const int ne = n - rigid;
  if (ne == 0) {
    // Every mode rigid (a held subsystem with no spring left): a drift only.
    lambda_.resize(0);
    v_.resize(2 * n, 0);
    v_inv_.resize(0, 2 * n);
    weight_.resize(0);
    return;
  }
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * ne, 2 * ne);
  a.topRightCorner(ne, ne).setIdentity();
  if (rigid > 0) {
    a.bottomLeftCorner(ne, ne) = (-omega2).asDiagonal();
    a.bottomRightCorner(ne, ne) = -elastic.transpose() * c * elastic;
  } else {
    const Eigen::LDLT<Eigen::MatrixXd> m_ldlt(mass);
    a.bottomLeftCorner(n, n) = -m_ldlt.solve(stiffness);
    a.bottomRightCorner(n, n) = -m_ldlt.solve(c);
  }
  const Eigen::EigenSolver<Eigen::MatrixXd> eig(a);
  NSMODAL_CHECK(eig.info() == Eigen::Success);
  Eigen::MatrixXcd v = eig.eigenvectors();
  for (int j = 0; j < 2 * ne; ++j) v.col(j).normalize();
  const Eigen::PartialPivLU<Eigen::MatrixXcd> v_lu(v);
  if (!(v_lu.rcond() * kMaxModeCondition > 1.0)) {
    throw InputError("system", "has a nearly critically damped mode (the first-order modes are nearly "
                               "parallel, condition number " +
                                   FormatValue(1.0 / v_lu.rcond()) + " > " + FormatValue(kMaxModeCondition) +
                                   "): the closed-form flight needs damping ratios away from 1");
  }
  Eigen::MatrixXcd v_inv = v_lu.inverse();
  if (rigid > 0) {
    // z = (Phi_e x_e, Phi_e v_e) on the complement, (x_e, v_e) = (Phi_e' M) z.
    const Eigen::MatrixXcd to_elastic = (elastic.transpose() * mass).cast<std::complex<double>>();
    const Eigen::MatrixXcd phi_e = elastic.cast<std::complex<double>>();
    Eigen::MatrixXcd v_full(2 * n, 2 * ne), v_inv_full(2 * ne, 2 * n);
    v_full << phi_e * v.topRows(ne), phi_e * v.bottomRows(ne);
    v_inv_full << v_inv.leftCols(ne) * to_elastic, v_inv.rightCols(ne) * to_elastic;
    v = v_full;
    v_inv = v_inv_full;
  }
  std::vector<int> kept;
  for (int j = 0; j < 2 * ne; ++j) {
    if (eig.eigenvalues()[j].imag() >= 0.0) kept.push_back(j);
  }
  const int m = static_cast<int>(kept.size());
  lambda_.resize(m);
  v_.resize(2 * n, m);
  v_inv_.resize(m, 2 * n);
  weight_.resize(m);
  for (int k = 0; k < m; ++k) {
    std::complex<double> l = eig.eigenvalues()[kept[k]];
    // A positive semi-definite C gives Re lambda <= 0; the solver's round-off
    // (~1e-16 |lambda|) may put an undamped mode on either side: it is put
    // on the axis, which the signal bounds (|e^{mu s}| <= 1) rely on.
    if (!damped || l.real() > 0.0) l = {0.0, l.imag()};
    lambda_[k] = l;
    v_.col(k) = v.col(kept[k]);
    v_inv_.row(k) = v_inv.row(kept[k]);
    weight_[k] = eig.eigenvalues()[kept[k]].imag() > 0.0 ? 2.0 : 1.0;
  }
}

Eigen::VectorXcd ForcedFlow::Eigenvalues() const { return lambda_; }

Eigen::VectorXd ForcedFlow::Particular(double t) const {
  Eigen::VectorXd z(2 * n_);
  if (n_ == 0) return z;
  const std::complex<double> e = std::polar(1.0, w_ * t);
  const std::complex<double> iw(0.0, w_);
  z.head(n_) = x_static_ + (x_harmonic_ * e).real();
  z.tail(n_) = (x_harmonic_ * (iw * e)).real();
  return z;
}

void ForcedFlow::Advance(double t, double s, Eigen::Ref<Eigen::VectorXd> z) const {
  if (n_ == 0) return;
  const Eigen::VectorXd free = z - Particular(t);
  const Eigen::VectorXcd q = v_inv_ * free;
  Eigen::VectorXd out = Particular(t + s);
  for (int k = 0; k < lambda_.size(); ++k) {
    out += weight_[k] * (v_.col(k) * (q[k] * std::exp(lambda_[k] * s))).real();
  }
  if (rigid_modes() > 0) {
    // The drift: q + s q' and q'.
    const Eigen::VectorXd q0 = rigid_coord_ * free.head(n_), q1 = rigid_coord_ * free.tail(n_);
    out.head(n_) += rigid_ * (q0 + s * q1);
    out.tail(n_) += rigid_ * q1;
  }
  z = out;
}

void ForcedFlow::Observe(double t, const Eigen::Ref<const Eigen::VectorXd>& z,
                         const Eigen::Ref<const Eigen::RowVectorXd>& l, double c0, double c1,
                         DampedSignal& out) const {
  const int m = static_cast<int>(lambda_.size());
  const bool harmonic = w_ > 0.0;
  out.beta.resize(m + (harmonic ? 1 : 0));
  out.mu.resize(out.beta.size());
  out.offset = c0;
  out.slope = 0.0;
  if (n_ > 0) {
    out.offset += l.head(n_).dot(x_static_);
    const Eigen::VectorXd free = z - Particular(t);
    const Eigen::VectorXcd q = v_inv_ * free;
    const Eigen::RowVectorXcd lv = l.cast<std::complex<double>>() * v_;
    for (int k = 0; k < m; ++k) {
      out.beta[k] = weight_[k] * lv[k] * q[k];
      out.mu[k] = lambda_[k];
    }
    if (rigid_modes() > 0) {
      const Eigen::VectorXd x0 = rigid_ * (rigid_coord_ * free.head(n_)), x1 = rigid_ * (rigid_coord_ * free.tail(n_));
      out.offset += l.head(n_).dot(x0) + l.tail(n_).dot(x1);
      out.slope = l.head(n_).dot(x1);
    }
  }
  if (harmonic) {
    // l' z_p's oscillating part plus c1 cos(w t), as Re[beta e^{i w s}].
    const std::complex<double> iw(0.0, w_);
    std::complex<double> amp = c1;
    if (n_ > 0) {
      amp += l.head(n_).cast<std::complex<double>>().dot(x_harmonic_) +
             iw * l.tail(n_).cast<std::complex<double>>().dot(x_harmonic_);
    }
    // Eigen's complex dot conjugates its first argument; l is real.
    out.beta[m] = amp * std::polar(1.0, w_ * t);
    out.mu[m] = iw;
  }
  out.UpdateBounds();
}

Eigen::MatrixXd ForcedFlow::Transition(double s) const {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(2 * n_, 2 * n_);
  for (int k = 0; k < lambda_.size(); ++k) {
    out += weight_[k] * (v_.col(k) * std::exp(lambda_[k] * s) * v_inv_.row(k)).real();
  }
  if (rigid_modes() > 0) {
    const Eigen::MatrixXd p = rigid_ * rigid_coord_;  // the M-orthogonal projector on ker K
    out.topLeftCorner(n_, n_) += p;
    out.topRightCorner(n_, n_) += s * p;
    out.bottomRightCorner(n_, n_) += p;
  }
  return out;
}

}  // namespace nsmodal
