#include "nsmodal/two_impact.h"

#include <algorithm>
#include <cmath>

#include "nsmodal/flow.h"
#include "nsmodal/return_map.h"
#include "nsmodal/roots.h"

namespace nsmodal {

std::vector<double> TwoImpactRoots(const ModalBasis& b, double period, const TwoImpactOptions& options) {
  const double half = 0.5 * period;
  // An even number of cells so that T/2 is a grid node.
  int cells = static_cast<int>(std::ceil(period / std::min(options.t2_step, period / 64.0)));
  cells += cells % 2;
  auto indicator = [&](double t2) { return TwoImpactIndicator(b, t2, period); };
  std::vector<double> roots{half};
  double t_prev = period / cells;
  double f_prev = indicator(t_prev);
  for (int j = 2; j < cells; ++j) {
    const double t = period * j / cells;
    const double f = indicator(t);
    if ((f_prev < 0.0) != (f < 0.0) || f == 0.0) {
      const double root = f == 0.0 ? t : PolishRoot(indicator, t_prev, t);
      const bool at_half = std::abs(root - half) <= 1e-9 * period;
      if (!at_half) {
        Eigen::JacobiSVD<Eigen::MatrixXd> svd(MatrixA(b, {root}, period));
        if (svd.singularValues().minCoeff() < options.kernel_tol) roots.push_back(root);
      }
    }
    t_prev = t;
    f_prev = f;
  }
  std::sort(roots.begin(), roots.end());
  roots.erase(std::unique(roots.begin(), roots.end()), roots.end());
  return roots;
}

Orbit TwoImpactOrbitAt(const ModalBasis& b, double t2, double period, const TwoImpactOptions& options) {
  const int dim = 2 * b.n;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(MatrixA(b, {t2}, period), Eigen::ComputeFullV);
  const Eigen::VectorXd k1 = svd.matrixV().col(dim - 1);
  const Eigen::VectorXd k2 = svd.matrixV().col(dim - 2);
  // NC2: x_c(0) = d and x_c(t2-) = d for y0 = alpha k1 + beta k2.
  Eigen::VectorXd s1 = k1, s2 = k2;
  Flow(b, t2, s1);
  Flow(b, t2, s2);
  Eigen::Matrix2d c;
  c << ContactPosition(b, k1), ContactPosition(b, k2), ContactPosition(b, s1), ContactPosition(b, s2);
  const Eigen::Vector2d rhs(b.gap, b.gap);
  Eigen::JacobiSVD<Eigen::Matrix2d> csvd(c, Eigen::ComputeFullU | Eigen::ComputeFullV);
  // The two conditions coincide (rank 1) when the smaller singular value is at
  // round-off level of the larger: then a line of y0 satisfies NC2.
  const bool degenerate = csvd.singularValues()[1] <= 1e-10 * csvd.singularValues()[0];
  Eigen::Vector2d coef;
  if (degenerate) {
    csvd.setThreshold(1e-10);
    coef = csvd.solve(rhs);  // the minimum-norm member of the continuum
  } else {
    coef = c.partialPivLu().solve(rhs);
  }
  Orbit orbit = EvaluateOrbit(b, coef[0] * k1 + coef[1] * k2, {t2}, period, options.admissibility);
  orbit.degenerate = degenerate;
  return orbit;
}

std::vector<Orbit> TwoImpactOrbits(const ModalBasis& b, double period, const TwoImpactOptions& options) {
  std::vector<Orbit> out;
  for (double t2 : TwoImpactRoots(b, period, options)) out.push_back(TwoImpactOrbitAt(b, t2, period, options));
  return out;
}

}  // namespace nsmodal
