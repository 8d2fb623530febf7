#pragma once
// Exact free flight S(t) (paper eqs. 7-8, 13) and the impact map N (eqs. 9-12,
// 14) on the scaled modal state y = (u, s) of modal_basis.h.
#include <Eigen/Dense>
#include <utility>

#include "nsmodal/modal_basis.h"

namespace nsmodal {

// y <- S(t) y: a rotation by w_i t in each modal plane.
void Flow(const ModalBasis& b, double t, Eigen::Ref<Eigen::VectorXd> y);
// y <- N y with restitution e: s <- s - (1 + e) r (r.s) / |r|^2, so v_c -> -e v_c.
void Impact(const ModalBasis& b, double e, Eigen::Ref<Eigen::VectorXd> y);
// The same at contact j (b.contacts[j]): s <- s - (1 + e) r_j (r_j.s) / |r_j|^2.
void Impact(const ModalBasis& b, const ModalContact& contact, double e, Eigen::Ref<Eigen::VectorXd> y);

// The analysis's impact (e = AnalysisBasis::kRestitution = 1): a reflection.
inline void ElasticImpact(const AnalysisBasis& b, Eigen::Ref<Eigen::VectorXd> y) {
  Impact(b, AnalysisBasis::kRestitution, y);
}
Eigen::MatrixXd FlowMatrix(const ModalBasis& b, double t);
Eigen::MatrixXd ImpactMatrix(const ModalBasis& b, double e);
Eigen::MatrixXd ImpactMatrix(const ModalBasis& b, const ModalContact& contact, double e);

inline double ContactPosition(const ModalBasis& b, const Eigen::Ref<const Eigen::VectorXd>& y) {
  return b.r_over_omega.dot(y.head(b.n));
}
inline double ContactVelocity(const ModalBasis& b, const Eigen::Ref<const Eigen::VectorXd>& y) {
  return b.r.dot(y.tail(b.n));
}
// The same for contact j's projection (b.contacts[j]): n_j . x and n_j . v.
inline double ContactPosition(const ModalBasis& b, const ModalContact& c, const Eigen::Ref<const Eigen::VectorXd>& y) {
  return c.r_over_omega.dot(y.head(b.n));
}
inline double ContactVelocity(const ModalBasis& b, const ModalContact& c, const Eigen::Ref<const Eigen::VectorXd>& y) {
  return c.r.dot(y.tail(b.n));
}
// E = v'Mv/2 + x'Kx/2 = |y|^2 / 2 less the rigid-body modes' positions u_i
// (i < rigid), which store no energy.
inline double Energy(const ModalBasis& b, const Eigen::Ref<const Eigen::VectorXd>& y) {
  return 0.5 * (y.squaredNorm() - y.head(b.rigid).squaredNorm());
}

// A sum of sinusoids with an offset and a drift,
//   f(t) = c + p t + sum_i a_i cos(w_i t) + b_i sin(w_i t):
// x_c(t) on a flight (p: the rigid-body modes' drift, modal_basis.h), or the
// contact force while sticking. The bounds |f^(k)(t)| <= sum_i w_i^k
// sqrt(a_i^2 + b_i^2) (k >= 2; k = 1 adds |p|) make root isolation provable.
struct SinusoidSum {
  double offset = 0.0;
  double slope = 0.0;  // p
  Eigen::VectorXd a, b, omega;
  // bound[k] >= sup |f^(k)| for k = 1..6; bound[0] = sum of the amplitudes.
  double bound[7] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};

  SinusoidSum() = default;
  SinusoidSum(double c, Eigen::VectorXd a_in, Eigen::VectorXd b_in, Eigen::VectorXd omega_in);
  double Position(double t) const;
  double Velocity(double t) const;
  double Acceleration(double t) const;
  // First and second derivative from one sin/cos per term: the inner loop of NC3.
  std::pair<double, double> VelocityAcceleration(double t) const;
  // The value and the first three derivatives at t.
  void Derivatives(double t, double out[4]) const;
  // The same from the cosines and sines of w_i t, computed by the caller.
  void Derivatives(double t, const double* cos_wt, const double* sin_wt, double out[4]) const;
  // Recomputes `bound` after a, b, omega or slope changed.
  void UpdateBounds();
};

// x_c(t) = n_1 . x(t) on one flight segment from state y at t = 0 (or
// n_j . x(t) for contact j's ModalContact).
struct ContactSignal : SinusoidSum {
  ContactSignal(const ModalBasis& basis, const Eigen::Ref<const Eigen::VectorXd>& y);
  ContactSignal(const ModalBasis& basis, const ModalContact& contact, const Eigen::Ref<const Eigen::VectorXd>& y);
  // Reuses the storage for a new state (the simulator's inner loop).
  void Reset(const ModalBasis& basis, const Eigen::Ref<const Eigen::VectorXd>& y);
  void Reset(const ModalBasis& basis, const ModalContact& contact, const Eigen::Ref<const Eigen::VectorXd>& y);

 private:
  void Reset(const ModalBasis& basis, const Eigen::VectorXd& r_over_omega, const Eigen::Ref<const Eigen::VectorXd>& y);
};

}  // namespace nsmodal
