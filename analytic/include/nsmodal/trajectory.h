#pragma once
// One period of an analytic orbit in physical coordinates, in closed form:
// free flight S(t) between the impacts, the impact map N at each t_i (e = 1).
// For figures and for comparing with a simulation sample by sample.
#include <Eigen/Dense>

#include "nsmodal/modal_basis.h"
#include "nsmodal/orbit.h"

namespace nsmodal {

// Rows (t, x_1..x_N, v_1..v_N) at `samples` evenly spaced times of each
// flight plus both ends of it: an impact time appears twice, with the velocity
// just before and just after, so the jump of v_c is drawn as a jump.
// t runs over [0, T]. samples >= 2.
Eigen::MatrixXd OrbitTrajectory(const AnalysisBasis& b, const Orbit& orbit, int samples);

// The same orbit started at time `shift` instead of 0 (its state there, with
// the impact times moved accordingly): the orbit's own time shift, used to
// draw a 1-ipp orbit shifted by half a period (paper Fig. 13).
Eigen::MatrixXd ShiftTrajectory(const Eigen::MatrixXd& trajectory, double shift, double period);

}  // namespace nsmodal
