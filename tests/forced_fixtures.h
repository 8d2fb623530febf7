#pragma once
// Independent evaluations of the damped, forced model (model.h), shared by
// the flight and the simulator tests: none of them calls forced_flow.h.
#include <Eigen/Dense>
#include <complex>

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
  m.restitution = 0.8;
  m.damping = RayleighDamping(m.mass, m.stiffness, 0.05, 0.02);
  m.forcing.amplitude = Eigen::Vector2d(0.3, 0.1);
  m.forcing.constant = Eigen::Vector2d(0.05, -0.02);
  m.forcing.frequency = 0.5;
  return m;
}

}  // namespace nsmodal::testing
