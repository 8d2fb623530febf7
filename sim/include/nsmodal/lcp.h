#pragma once
// The one-step nonsmooth problem of several contacts (Siconos' OneStepNSProblem):
// a linear complementarity problem
//   w = A z + q,   0 <= z  _|_  w >= 0,
// solved by Siconos Numerics' lexicographic Lemke method (pivoting: exact up
// to round-off, finite, and it handles the degenerate problems simultaneous
// impacts give). A is a Delassus matrix H M^-1 H' (or H W^-1 H' for
// Moreau-Jean): symmetric positive definite when the contact normals are
// independent, and then the LCP has exactly one solution.
#include <Eigen/Dense>
#include <string>

namespace nsmodal {

struct LcpSolution {
  bool solved = false;
  Eigen::VectorXd z, w;
  std::string message;  // why not, when !solved
};

// One contact takes the closed form (z = max(0, -q / a)); two or more Lemke.
// solved is false (with Siconos' status in `message`) when Lemke fails or
// its answer violates complementarity by more than 1e-10 of the scale of q.
LcpSolution SolveLcp(const Eigen::MatrixXd& a, const Eigen::VectorXd& q);

}  // namespace nsmodal
