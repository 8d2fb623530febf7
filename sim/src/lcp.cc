#include "nsmodal/lcp.h"

#include <cmath>
#include <algorithm>
#include <cstdlib>

#include <siconos/numerics/LinearComplementarityProblem.h>
#include <siconos/numerics/NonSmoothDrivers.h>
#include <siconos/numerics/NumericsMatrix.h>
#include <siconos/numerics/SolverOptions.h>
#include <siconos/numerics/lcp_cst.h>

namespace nsmodal {

LcpSolution SolveLcp(const Eigen::MatrixXd& a, const Eigen::VectorXd& q) {
  const int n = static_cast<int>(q.size());
  LcpSolution out;
  out.z = Eigen::VectorXd::Zero(n);
  out.w = q;
  if (n == 0) {
    out.solved = true;
    return out;
  }
  if (n == 1) {
    if (q[0] < 0.0) {
      out.z[0] = -q[0] / a(0, 0);
      out.w[0] = 0.0;
    }
    out.solved = a(0, 0) > 0.0;
    if (!out.solved) out.message = "the Delassus matrix is not positive";
    return out;
  }
  // Siconos owns the problem's storage (freeLinearComplementarityProblem frees M and q).
  LinearComplementarityProblem* problem = newLCP();
  problem->size = n;
  problem->M = NM_create(NM_DENSE, n, n);
  Eigen::Map<Eigen::MatrixXd>(problem->M->matrix0, n, n) = a;  // column-major, as Siconos
  problem->q = static_cast<double*>(std::malloc(sizeof(double) * n));
  Eigen::Map<Eigen::VectorXd>(problem->q, n) = q;
  SolverOptions* options = solver_options_create(SICONOS_LCP_LEMKE);
  const int info = linearComplementarity_driver(problem, out.z.data(), out.w.data(), options);
  solver_options_delete(options);
  freeLinearComplementarityProblem(problem);
  // Check the answer ourselves: complementarity and signs to round-off of q's scale.
  const double scale = std::max(q.cwiseAbs().maxCoeff(), 1e-300);
  const Eigen::VectorXd w = a * out.z + q;
  const double violation = std::max({(-out.z).maxCoeff(), (-w).maxCoeff(), (out.z.cwiseProduct(w)).cwiseAbs().maxCoeff() /
                                                                              std::max(out.z.cwiseAbs().maxCoeff(), 1e-300)});
  out.w = w;
  out.solved = info == 0 && out.z.allFinite() && violation <= 1e-10 * scale;
  if (!out.solved) {
    out.message = "Siconos' Lemke solver returned " + std::to_string(info) + " with a complementarity violation of " +
                  std::to_string(violation / scale) + " of the scale";
  }
  return out;
}

}  // namespace nsmodal
