#pragma once
// NC2 and NC3 checked exactly, without sampling (DESIGN.md).
//
// On a flight segment x_c(t) is a sum of sinusoids (flow.h, ContactSignal).
// Its interior maxima are roots of v_c(t); IsolateRoots finds all of them using
// |dv_c/dt| <= sum w_i^2 amp_i, so a short excursion above d cannot be stepped over.
#include <Eigen/Dense>
#include <vector>

#include "nsmodal/modal_basis.h"
#include "nsmodal/orbit.h"

namespace nsmodal {

struct SegmentCheck {
  double max_excess;      // max of x_c - d over critical points in the open segment; -inf if none
  double t_at_max;        // where it is reached
  double start_velocity;  // v_c just after the segment starts
  double end_velocity;    // v_c just before the segment ends
  double position_scale;  // sum_i amp_i: the size of the terms of x_c (round-off scale)
  double velocity_scale;  // sum_i w_i amp_i
  // False when the search for interior maxima hit its work limit (1000 cells
  // per half-oscillation of the fastest mode, about 25 times what it needs):
  // NC3 is then undetermined and the orbit is not called admissible.
  bool complete = true;
};

SegmentCheck CheckSegment(const AnalysisBasis& b, const Eigen::Ref<const Eigen::VectorXd>& y, double duration);
// The same for contact j's n_j . x - d_j (b.contacts[j]).
SegmentCheck CheckSegment(const AnalysisBasis& b, const ModalContact& contact, const Eigen::Ref<const Eigen::VectorXd>& y,
                          double duration);

struct AdmissibilityOptions {
  // x_c - d may exceed 0 by rel_tol * max(d, position_scale): x_c is a sum of
  // terms of size position_scale, so its round-off is ~1e-16 of that; 1e-10
  // leaves six orders of room and is far below any excursion of physical interest.
  double rel_tol = 1e-10;
  // An orbit is potential when nc2_residual and periodicity_residual are below
  // this. Measured defects of potential orbits are ~1e-14 (see the benchmark);
  // 1e-8 flags a breakdown (ill-conditioned kernel near a singular transition).
  double potential_tol = 1e-8;
};

// Fills energy, residuals, NC3 margin, potential, admissible and reason of an
// orbit from y0, times and period (e = 1). sequence: the contact of each
// impact (0-based, m entries; empty: all on contact 1). NC2 on each impact's
// own contact; NC3 on every contact's gap over every flight, each impact
// arriving towards its wall and leaving it.
Orbit EvaluateOrbit(const AnalysisBasis& b, const Eigen::VectorXd& y0, const std::vector<double>& times,
                    double period, const AdmissibilityOptions& options = {}, std::vector<int> sequence = {});

}  // namespace nsmodal
