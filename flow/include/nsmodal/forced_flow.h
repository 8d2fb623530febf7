#pragma once
// Exact flight of a damped, forced linear system (DESIGN.md "Damping and
// forcing"):
//   M x'' + C x' + K x = f0 + f cos(w t).
// With z = (x, v) the flight is z' = A z + b(t), A = [[0, I], [-M^-1 K, -M^-1 C]].
// Its solution is the particular (steady-state) response plus the free one:
//   z_p(t) = (x_s + Re[X e^{i w t}], Re[i w X e^{i w t}]),
//   x_s = K^-1 f0,  X = (K - w^2 M + i w C)^-1 f  (the receptance times f),
//   z(t + s) = z_p(t + s) + V e^{Lambda s} V^-1 (z(t) - z_p(t)),
// with A = V Lambda V^-1 (complex pairs for underdamped modes, real
// eigenvalues for overdamped ones; Re lambda <= 0 for a positive
// semi-definite C). Any linear functional of the state along a flight is then
// a DampedSignal: a constant plus decaying complex exponentials plus one
// sinusoid at w, whose derivatives have closed-form bounds for s >= 0, so the
// guaranteed impact search of first_rise.h carries over.
//
// Rigid-body modes (K semi-definite: a free mass, an impact damper's ball,
// issue 24): with Phi_0 the M-orthonormal basis of ker K, the rigid
// coordinates q = Phi_0' M x fly as a free drift, q(t + s) = q + s q', when
// the damping leaves them alone (C Phi_0 = 0: the rigid motion is undamped,
// A has a 2 x 2 Jordan block at 0 per rigid mode) and no constant force
// pushes them (Phi_0' f0 = 0); the M-orthogonal complement is invariant
// (K and C vanish on Phi_0) and flies through the eigenvectors as above. The
// harmonic force's rigid part is in X (K - w^2 M + i w C is regular for w > 0).
//
// Limits (InputError): a nearly defective A (a mode at critical damping,
// zeta = 1, has one eigenvector for a double eigenvalue: the eigenvector
// matrix's condition number above kMaxModeCondition), and undamped resonant
// forcing (K - w^2 M + i w C singular: the steady state is unbounded).
#include <Eigen/Dense>
#include <complex>
#include <optional>
#include <string>

#include "nsmodal/model.h"

namespace nsmodal {

// f(s) = offset + slope s + Re sum_j beta_j exp(mu_j s), Re mu_j <= 0, for
// s >= 0 (slope: a rigid-body drift; 0 without one).
struct DampedSignal {
  double offset = 0.0, slope = 0.0;
  Eigen::VectorXcd beta, mu;
  // bound[k] >= sup_{s >= 0} |f^(k)(s)| = sum_j |beta_j| |mu_j|^k for k >= 2
  // (|exp(mu s)| <= 1), that plus |slope| for k = 1; bound[0] = sum_j
  // |beta_j|, the oscillating part's (a scale for tolerances).
  double bound[5] = {0.0, 0.0, 0.0, 0.0, 0.0};

  void UpdateBounds();
  double Position(double s) const;
  double Velocity(double s) const;
  double Acceleration(double s) const;
  // The value and the first three derivatives at s.
  void Derivatives(double s, double out[4]) const;
  // The largest |mu_j|: the signal's fastest time scale is 1 / MaxRate().
  double MaxRate() const;
};

// The steady-state amplitude X = (K - w^2 M + i w C)^-1 f (the receptance
// times f), or nullopt when K - w^2 M + i w C is singular to within
// kMinResonanceCondition (an undamped resonance). C may be empty.
inline constexpr double kMinResonanceCondition = 1e-12;  // below, X keeps < ~4 digits
std::optional<Eigen::VectorXcd> HarmonicResponse(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& damping,
                                                 const Eigen::MatrixXd& stiffness, const Eigen::VectorXd& force,
                                                 double frequency);

// The modes of (K, M) split at the rigid-body ones, for a damped or forced
// flight with a free part (forced_flow.h): the M-orthonormal Phi_0 (n x r)
// and the elastic Phi_e (n x (n - r)) with their eigenvalues omega2 (of K).
// Checked: the damping must leave the rigid motion alone (C Phi_0 = 0: a
// dashpot between masses, not to ground) and no constant force may push it
// (Phi_0' f0 = 0); throws InputError naming "system.damping_matrix" or
// "forcing.constant" otherwise (CVODE and Moreau-Jean need neither).
// damping and constant_force may be empty; rigid is RigidBodyModes(stiffness),
// which the caller has counted (one eigenvalue solve, not two).
struct RigidBodySplit {
  Eigen::MatrixXd rigid, elastic;
  Eigen::VectorXd omega2;
};
RigidBodySplit SplitRigidBody(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& damping,
                              const Eigen::MatrixXd& stiffness, const Eigen::VectorXd& constant_force, int rigid);

class ForcedFlow {
 public:
  // Above this the eigenvector matrix of A leaves fewer than 8 digits.
  static constexpr double kMaxModeCondition = 1e8;

  // M symmetric positive definite n x n, K symmetric positive semi-definite
  // (rigid-body modes as above), C symmetric positive semi-definite n x n or
  // empty, f0 and f of length n or empty; n may be 0 (every dof held).
  // frequency: w of the harmonic terms (0: none), kept even when f = 0 here,
  // for the c1 cos(w t) of Observe (a force acting only on a held dof).
  // Throws InputError naming "system" (a nearly defective mode),
  // "forcing.frequency" (undamped resonance), "system.damping_matrix" (damping
  // of a rigid-body motion) or "forcing.constant" (a constant force on one).
  ForcedFlow(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& damping, const Eigen::MatrixXd& stiffness,
             const Eigen::VectorXd& constant_force, const Eigen::VectorXd& force_amplitude, double frequency);
  explicit ForcedFlow(const Model& model);

  int dofs() const { return n_; }
  double frequency() const { return w_; }
  // x_s (K x_s = f0; its rigid part 0 with rigid-body modes).
  const Eigen::VectorXd& static_response() const { return x_static_; }
  const Eigen::VectorXcd& harmonic_response() const { return x_harmonic_; }  // X
  // The eigenvalues of A, one of each conjugate pair (Im >= 0), without the
  // rigid-body modes' (0, twice each: a drift).
  Eigen::VectorXcd Eigenvalues() const;
  int rigid_modes() const { return static_cast<int>(rigid_.cols()); }
  // Phi_0, M-orthonormal (n x rigid_modes()).
  const Eigen::MatrixXd& rigid_basis() const { return rigid_; }

  // z_p(t), the particular solution.
  Eigen::VectorXd Particular(double t) const;
  // z <- z(t + s), the flight from z = z(t).
  void Advance(double t, double s, Eigen::Ref<Eigen::VectorXd> z) const;
  // The signal l' z(t + s) + c0 + c1 cos(w (t + s)) for s >= 0 along the
  // flight from z = z(t); reuses out's storage.
  void Observe(double t, const Eigen::Ref<const Eigen::VectorXd>& z, const Eigen::Ref<const Eigen::RowVectorXd>& l,
               double c0, double c1, DampedSignal& out) const;
  // e^{A s}: the state transition matrix, d z(t + s) / d z(t).
  Eigen::MatrixXd Transition(double s) const;

 private:
  int n_ = 0;
  double w_ = 0.0;
  Eigen::VectorXd x_static_;
  Eigen::VectorXcd x_harmonic_;
  // The kept eigenvalues (Im >= 0), their eigenvectors and the matching rows
  // of V^-1, each kept pair weighted 2 (the conjugate adds the same real part).
  Eigen::VectorXcd lambda_;
  Eigen::MatrixXcd v_, v_inv_;
  Eigen::VectorXd weight_;
  // The rigid-body modes: Phi_0 (n x r) and Phi_0' M (r x n).
  Eigen::MatrixXd rigid_, rigid_coord_;
};

}  // namespace nsmodal
