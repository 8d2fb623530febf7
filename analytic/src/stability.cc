#include "nsmodal/stability.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "nsmodal/flow.h"

namespace nsmodal {
namespace {

// f(y) = G y: u_i' = w_i s_i, s_i' = -w_i u_i.
Eigen::VectorXd Field(const AnalysisBasis& b, const Eigen::VectorXd& y) {
  Eigen::VectorXd f(2 * b.n);
  f.head(b.n) = b.omega.cwiseProduct(y.tail(b.n));
  f.tail(b.n) = -b.omega.cwiseProduct(y.head(b.n));
  return f;
}

}  // namespace

Eigen::MatrixXd SaltationMatrix(const AnalysisBasis& b, const Eigen::VectorXd& y_minus) {
  const Eigen::MatrixXd reset = ImpactMatrix(b, AnalysisBasis::kRestitution);
  const Eigen::VectorXd y_plus = reset * y_minus;
  Eigen::VectorXd normal = Eigen::VectorXd::Zero(2 * b.n);
  normal.head(b.n) = b.r_over_omega;  // gradient of x_c
  const Eigen::VectorXd f_minus = Field(b, y_minus);
  const double rate = normal.dot(f_minus);  // v_c just before the impact
  return reset + (Field(b, y_plus) - reset * f_minus) * normal.transpose() / rate;
}

Stability OrbitStability(const AnalysisBasis& b, const Orbit& orbit, double tol) {
  Stability out;
  const int dim = 2 * b.n;
  Eigen::MatrixXd m = Eigen::MatrixXd::Identity(dim, dim);
  Eigen::VectorXd y = orbit.y0;
  double prev = 0.0;
  std::vector<double> ends = orbit.times;
  ends.push_back(orbit.period);
  // The largest |v_c| a state of this energy can have: |r| |y|.
  const double contact_speed_scale = b.r.norm() * orbit.y0.norm();
  for (double t : ends) {
    Flow(b, t - prev, y);
    if (!(std::abs(ContactVelocity(b, y)) > 1e-9 * contact_speed_scale)) out.defined = false;
    m = FlowMatrix(b, t - prev) * m;
    m = SaltationMatrix(b, y) * m;
    ElasticImpact(b, y);
    prev = t;
  }
  if (!out.defined) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    out.monodromy = Eigen::MatrixXd::Constant(dim, dim, nan);
    out.multipliers = Eigen::VectorXcd::Constant(dim, std::complex<double>(nan, nan));
    out.max_modulus = out.growth_per_period = nan;
    return out;
  }
  out.monodromy = m;
  Eigen::EigenSolver<Eigen::MatrixXd> es(m);
  std::vector<std::complex<double>> ev(es.eigenvalues().data(), es.eigenvalues().data() + dim);
  std::sort(ev.begin(), ev.end(), [](auto x, auto y) { return std::abs(x) > std::abs(y); });
  out.multipliers = Eigen::Map<Eigen::VectorXcd>(ev.data(), dim);
  out.max_modulus = std::abs(ev.front());
  out.growth_per_period = std::log(out.max_modulus);
  out.stable = out.max_modulus <= 1.0 + tol;
  return out;
}

}  // namespace nsmodal
