#include "nsmodal/one_impact.h"

#include <cmath>

#include "nsmodal/flow.h"
#include "nsmodal/return_map.h"

namespace nsmodal {

double SingularFunction(const AnalysisBasis& b, double period, int contact) {
  b.RequireElastic("1-impact orbits");
  const Eigen::VectorXd& r = b.contacts[contact].r;
  double d = 0.0;
  for (int i = 0; i < b.n; ++i) {
    const double h = 0.5 * b.omega[i] * period;
    d += r[i] * r[i] * std::cos(h) / (std::sin(h) * b.omega[i]);
  }
  return d;
}

Eigen::VectorXd OneImpactState(const AnalysisBasis& b, double period, int contact) {
  const Eigen::VectorXd& r = b.contacts[contact].r;
  const double scale = b.contacts[contact].gap / SingularFunction(b, period, contact);
  Eigen::VectorXd y0(2 * b.n);
  for (int i = 0; i < b.n; ++i) {
    const double h = 0.5 * b.omega[i] * period;
    y0[i] = scale * r[i] * std::cos(h) / std::sin(h);
    y0[b.n + i] = scale * r[i];
  }
  return y0;
}

Orbit OneImpactOrbit(const AnalysisBasis& b, double period, const AdmissibilityOptions& options, int contact) {
  const double denom = SingularFunction(b, period, contact);
  const Eigen::VectorXd y0 = OneImpactState(b, period, contact);
  if (!y0.allFinite() || denom == 0.0) {
    Orbit o;
    o.period = period;
    o.y0 = y0;
    o.sequence = {contact};
    o.reason = "not potential: T is singular (D(T) = 0) or a multiple of a linear period";
    return o;
  }
  return EvaluateOrbit(b, y0, {}, period, options, {contact});
}

Orbit OneImpactOrbitFromKernel(const AnalysisBasis& b, double period, const AdmissibilityOptions& options) {
  b.RequireElastic("1-impact orbits");
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(MatrixA(b, {}, period), Eigen::ComputeFullV);
  Eigen::VectorXd k = svd.matrixV().col(2 * b.n - 1);
  k *= b.gap / ContactPosition(b, k);
  return EvaluateOrbit(b, k, {}, period, options);
}

double OneImpactContactPosition(const AnalysisBasis& b, double period, double t) {
  double sum = 0.0;
  for (int i = 0; i < b.n; ++i) {
    sum += b.r[i] * b.r[i] * std::cos(b.omega[i] * (t - 0.5 * period)) /
           (b.omega[i] * std::sin(0.5 * b.omega[i] * period));
  }
  return b.gap * sum / SingularFunction(b, period);
}

}  // namespace nsmodal
