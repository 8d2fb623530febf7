#include "nsmodal/lcp.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace nsmodal {

LcpSolution SolveLcp(const Eigen::MatrixXd& a, const Eigen::VectorXd& q) {
  const int n = static_cast<int>(q.size());
  LcpSolution out;
  out.z = Eigen::VectorXd::Zero(n);
  out.w = q;
  if (n > kMaxLcpSize) {
    out.message = "an LCP of " + std::to_string(n) + " contacts: at most " + std::to_string(kMaxLcpSize);
    return out;
  }
  std::vector<bool> active(n, false);  // z_i basic (w_i = 0)
  const long max_pivots = 1L << n;
  for (long pivot = 0; pivot <= max_pivots; ++pivot) {
    std::vector<int> idx;
    for (int i = 0; i < n; ++i) {
      if (active[i]) idx.push_back(i);
    }
    const int k = static_cast<int>(idx.size());
    out.z.setZero();
    if (k > 0) {
      Eigen::MatrixXd block(k, k);
      Eigen::VectorXd rhs(k);
      for (int r = 0; r < k; ++r) {
        rhs[r] = -q[idx[r]];
        for (int c = 0; c < k; ++c) block(r, c) = a(idx[r], idx[c]);
      }
      const Eigen::FullPivLU<Eigen::MatrixXd> lu(block);
      if (!lu.isInvertible()) {
        out.message = "the Delassus matrix of the contacts struck at once is singular (dependent normals)";
        return out;
      }
      const Eigen::VectorXd zb = lu.solve(rhs);
      for (int r = 0; r < k; ++r) out.z[idx[r]] = zb[r];
    }
    out.w = a * out.z + q;
    for (int i : idx) out.w[i] = 0.0;  // exactly, by construction
    // The least index with a wrong sign: a basic z < 0 or a nonbasic w < 0.
    int flip = -1;
    for (int i = 0; i < n && flip < 0; ++i) {
      if (active[i] ? out.z[i] < 0.0 : out.w[i] < 0.0) flip = i;
    }
    if (flip < 0) {
      // Check the answer: signs and complementarity to round-off of q's scale.
      const double scale = std::max(q.cwiseAbs().maxCoeff(), 1e-300);
      const Eigen::VectorXd w = a * out.z + q;
      double violation = 0.0;
      for (int i = 0; i < n; ++i) {
        violation = std::max({violation, -out.z[i], -w[i], std::min(std::abs(out.z[i]) * a(i, i), std::abs(w[i]))});
      }
      out.solved = std::isfinite(violation) && violation <= 1e-10 * scale;
      if (!out.solved) out.message = "the pivoting ended with a complementarity violation of " +
                                     std::to_string(violation / scale) + " of the scale";
      return out;
    }
    active[flip] = !active[flip];
    ++out.pivots;
  }
  out.message = "no solution after " + std::to_string(max_pivots) + " flips (the matrix is not a P-matrix)";
  return out;
}

}  // namespace nsmodal
