#pragma once
// Periodic orbits with one impact per period (paper section 2.1).
//
// A_1(T) = N S(T) - I is orthogonal minus I with det(N S) = -1, so ker A_1 has
// dimension >= 1 for every T. Solving it in closed form (the orbit is symmetric,
// x(t) = x(T - t), each mode q_i = a_i cos(w_i (t - T/2))) gives, with
//   D(T) = sum_i r_i^2 cot(w_i T / 2) / w_i            (singular when D = 0, eq. 23)
// the post-impact state y0 = (d / D(T)) (r_i cot(w_i T/2), r_i)_i, and
//   x_c(t) = d / D(T) * sum_i r_i^2 cos(w_i (t - T/2)) / (w_i sin(w_i T/2))   (eqs. 21-22)
// The paper's eq. 22 prints cot(w_i T) in A(T); the kernel computation (tests)
// shows it must read cot(w_i T / 2), with the opposite sign on B2.
#include <vector>

#include "nsmodal/admissibility.h"
#include "nsmodal/modal_basis.h"
#include "nsmodal/orbit.h"

namespace nsmodal {

// Each function takes the contact struck (0-based, default contact 1): with
// several contacts r is that contact's Phi' n_j and d its gap (the orbit of
// the sequence (j); NC3 then checks every other contact's gap too).
double SingularFunction(const AnalysisBasis& b, double period, int contact = 0);  // D(T)

// The post-impact state y0 of the 1-ipp orbit of period T (scaled modal, the
// closed form above), O(N) and nothing else: no NC3 search (whose work grows
// with w_max T). Not finite where D(T) = 0 or T = k T_i.
Eigen::VectorXd OneImpactState(const AnalysisBasis& b, double period, int contact = 0);

// The potential 1-ipp orbit of period T in closed form, evaluated (NC2, NC3,
// periodicity by propagation). potential = false where D(T) = 0 or T = k T_i.
Orbit OneImpactOrbit(const AnalysisBasis& b, double period, const AdmissibilityOptions& options = {}, int contact = 0);

// The same orbit from the kernel of A_1 (SVD), scaled so that x_c(0) = d: the
// paper's route, kept as an independent check of the closed form.
Orbit OneImpactOrbitFromKernel(const AnalysisBasis& b, double period, const AdmissibilityOptions& options = {});

// x_c(t) of the 1-ipp orbit of period T, eq. 21 in general-N form.
double OneImpactContactPosition(const AnalysisBasis& b, double period, double t);

}  // namespace nsmodal
