#pragma once
// The return map of an m-impact periodic orbit (paper eqs. 15-17, 25) in the
// scaled modal coordinates of modal_basis.h. With impact times
// 0 = t1 < t2 < ... < tm < T and y0 the state just AFTER the impact at t = 0,
//   Q_m = N S(T - tm) N S(tm - t_{m-1}) ... N S(t2),    A_m = Q_m - I.
// (Eq. 17 of the paper drops the last N; eq. 25 has it. The form above is right.)
// NC1: det A_m = 0.  For e = 1, Q_m is orthogonal with det (-1)^m.
#include <Eigen/Dense>
#include <vector>

#include "nsmodal/modal_basis.h"

namespace nsmodal {

// times = {t2, ..., tm} (t1 = 0 is implicit); period T. sequence: the
// contact of each impact (0-based, m entries: N is then N_{j_i}, each
// contact's own reflection); empty: every impact on contact 1.
Eigen::MatrixXd ReturnMap(const AnalysisBasis& b, const std::vector<double>& times, double period,
                          const std::vector<int>& sequence = {});
inline Eigen::MatrixXd MatrixA(const AnalysisBasis& b, const std::vector<double>& times, double period,
                               const std::vector<int>& sequence = {}) {
  return ReturnMap(b, times, period, sequence) - Eigen::MatrixXd::Identity(2 * b.n, 2 * b.n);
}

// Pfaffian of a skew-symmetric matrix (Parlett-Reid elimination with pivoting);
// Pf(A)^2 = det(A).
double Pfaffian(Eigen::MatrixXd a);

// The smooth signed NC1 indicator for m = 2. det A_2 >= 0 touches zero at its
// roots (DESIGN.md): Q_2 is a rotation with eigenvalue pairs exp(+-i theta_k),
// det(Q - I) = prod 4 sin^2(theta_k / 2). Instead we use
//   F(t2, T) = Pf(Q_2 - Q_2^T) = prod (+-2 sin theta_k),  F^2 = det(Q-I) det(Q+I),
// a polynomial in the entries of Q_2, which changes sign where a pair crosses 1
// (a root of det A_2) or -1 (rejected afterwards by checking det(Q + I)).
double TwoImpactIndicator(const AnalysisBasis& b, double t2, double period);

// The k right singular vectors of A_m(times, T) of smallest singular value
// (`basis`, 2N x k: the kernel where it exists, NC1), the k-th smallest
// singular value, and c(i, j) = x_c of basis vector j at impact i (i = 0: just
// after the impact at t = 0; i > 0: just before the impact at t_i), so that
// NC2 for y0 = basis * alpha reads c * alpha = d. False (out untouched) when
// the times are not increasing inside (0, T).
struct KernelContacts {
  Eigen::MatrixXd basis, c;
  double sigma_k = 0.0;
};
bool KernelAtImpacts(const AnalysisBasis& b, const std::vector<double>& times, double period, int k,
                     KernelContacts& out, const std::vector<int>& sequence = {});

// Dimension of ker A: singular values of A below tol (A is O(1) for e = 1).
int KernelDimension(const Eigen::MatrixXd& a, double tol);

}  // namespace nsmodal
