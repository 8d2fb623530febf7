#include "nsmodal/return_map.h"

#include <cmath>

#include "nsmodal/flow.h"
#include "nsmodal/check.h"

namespace nsmodal {

Eigen::MatrixXd ReturnMap(const AnalysisBasis& b, const std::vector<double>& times, double period,
                          const std::vector<int>& sequence) {
  const int dim = 2 * b.n;
  Eigen::MatrixXd q = Eigen::MatrixXd::Identity(dim, dim);
  double previous = 0.0;
  int impact = 1;  // the impact at the end of the flight: 1, ..., m - 1, then 0 (at T)
  const int m = static_cast<int>(times.size()) + 1;
  auto advance = [&](double dt) {
    const ModalContact& c = b.contacts[sequence.empty() ? 0 : sequence[impact % m]];
    for (int col = 0; col < dim; ++col) {
      Flow(b, dt, q.col(col));
      Impact(b, c, AnalysisBasis::kRestitution, q.col(col));
    }
    ++impact;
  };
  for (double t : times) {
    advance(t - previous);
    previous = t;
  }
  advance(period - previous);
  return q;
}

bool KernelAtImpacts(const AnalysisBasis& b, const std::vector<double>& times, double period, int k,
                     KernelContacts& out, const std::vector<int>& sequence) {
  double prev = 0.0;
  for (double t : times) {
    if (!(t > prev)) return false;
    prev = t;
  }
  if (!(prev < period)) return false;
  const int dim = 2 * b.n, impacts = static_cast<int>(times.size()) + 1;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(MatrixA(b, times, period, sequence), Eigen::ComputeFullV);
  out.basis = svd.matrixV().rightCols(k);
  out.sigma_k = svd.singularValues()[dim - k];
  out.c.resize(impacts, k);
  Eigen::MatrixXd y = out.basis;
  prev = 0.0;
  // y0 is the state just after the impact at t = 0: record x_c there, then
  // flow to each t_i, record x_c (NC2) and apply that impact.
  for (int i = 0; i < impacts; ++i) {
    const ModalContact& c = b.contacts[sequence.empty() ? 0 : sequence[i]];
    for (int j = 0; j < k; ++j) {
      if (i > 0) Flow(b, times[i - 1] - prev, y.col(j));
      out.c(i, j) = ContactPosition(b, c, y.col(j));
      if (i > 0) Impact(b, c, AnalysisBasis::kRestitution, y.col(j));
    }
    if (i > 0) prev = times[i - 1];
  }
  return true;
}

double Pfaffian(Eigen::MatrixXd a) {
  const int n = static_cast<int>(a.rows());
  NSMODAL_CHECK(a.cols() == n);
  if (n % 2 == 1) return 0.0;
  double pf = 1.0;
  for (int k = 0; k + 1 < n; k += 2) {
    int kp = k + 1;
    a.col(k).tail(n - k - 1).cwiseAbs().maxCoeff(&kp);
    kp += k + 1;
    if (kp != k + 1) {
      a.row(k + 1).swap(a.row(kp));
      a.col(k + 1).swap(a.col(kp));
      pf = -pf;
    }
    if (a(k + 1, k) == 0.0) return 0.0;
    pf *= a(k, k + 1);
    const int rest = n - k - 2;
    if (rest > 0) {
      const Eigen::VectorXd tau = a.row(k).tail(rest).transpose() / a(k, k + 1);
      const Eigen::VectorXd col = a.col(k + 1).tail(rest);
      a.bottomRightCorner(rest, rest) += tau * col.transpose() - col * tau.transpose();
    }
  }
  return pf;
}

double TwoImpactIndicator(const AnalysisBasis& b, double t2, double period) {
  b.RequireElastic("the 2-impact indicator Pf(Q_2 - Q_2')");
  const Eigen::MatrixXd q = ReturnMap(b, {t2}, period);
  return Pfaffian(q - q.transpose());
}

int KernelDimension(const Eigen::MatrixXd& a, double tol) {
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(a);
  int dim = 0;
  for (int i = 0; i < svd.singularValues().size(); ++i) dim += svd.singularValues()[i] < tol ? 1 : 0;
  return dim;
}

}  // namespace nsmodal
