#pragma once
// The one-step nonsmooth problem of several contacts (Siconos' OneStepNSProblem):
// a linear complementarity problem
//   w = A z + q,   0 <= z  _|_  w >= 0,
// with A a Delassus matrix H M^-1 H' (or H W^-1 H' for Moreau-Jean):
// symmetric positive definite when the contact normals are independent, and
// then the LCP has exactly one solution.
//
// Solved by Murty's least-index principal pivoting: guess the set of
// contacts with an impulse (z > 0, w = 0), solve that block, and flip the
// least index that violates a sign; for a P-matrix (an SPD one is) it
// terminates in a finite number of flips (Murty 1974; Cottle, Pang and
// Stone, The Linear Complementarity Problem, 4.2), bounded here by 2^n.
//
// Why not Siconos Numerics' Lemke solver (Debian's libsiconos-numerics-dev)?
// It was used first: it links OpenBLAS, MUMPS and gfortran's libquadmath,
// whose load-time printf hook sends every printf of the process down glibc's
// slow positional path: measured, every CSV table 8-13 % slower to write, for
// a problem of 2 to 4 unknowns. contacts_test checks this solver against the
// enumeration of every index set.
#include <Eigen/Dense>
#include <string>

namespace nsmodal {

struct LcpSolution {
  bool solved = false;
  Eigen::VectorXd z, w;
  int pivots = 0;       // the flips made
  std::string message;  // why not, when !solved
};

// n <= kMaxLcpSize unknowns. solved is false, with the reason, when a block
// of A is singular (dependent contact normals), the flips exceed 2^n, or the
// answer violates complementarity by more than 1e-10 of the scale of q.
inline constexpr int kMaxLcpSize = 24;
LcpSolution SolveLcp(const Eigen::MatrixXd& a, const Eigen::VectorXd& q);

}  // namespace nsmodal
