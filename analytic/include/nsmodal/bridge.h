#pragma once
// The bridge between the 1-ipp and 2-ipp nonsmooth modes (paper section 4,
// Figs. 13-15).
//
// At a grazing transition T_G (transitions.h) the 1-ipp orbit y_G touches d at
// an interior time t_g with zero velocity: a contact with no effect, so y_G is
// also a 2-ipp orbit with t2 = t_g, and (t_g, T_G) is a root of det A_2. There
// ker A_2 has dimension 2 and the two NC2 conditions x_c(0) = d, x_c(t_g) = d
// coincide, so NC2 leaves a line of initial states:
//   y(s) = y_G + s k,   k in ker A_2, x_c(k) = 0, |k| = 1,
// every one a potential 2-ipp orbit of the same period T_G, with energy
//   E(s) = E_G + s (y_G . k) + s^2 / 2        (E = |y|^2 / 2, modal_basis.h).
// The admissible ones form the interval s in [0, s_end] (k's sign chosen so),
// a vertical segment in the frequency-energy plot.
// The 1-ipp orbit is symmetric, x(t) = x(T - t), so it also grazes at T - t_g;
// started there it is again a 2-ipp orbit with t2 = t_g. On the paper's system
// (tests) that time shift is the far end y(s_end), E(s) is symmetric about
// s_end / 2, and the middle is the lowest-energy orbit of the continuum, which
// lies on a 2-ipp branch. When t_g = T_G / 2 the shift is half a period and the
// middle is the 1-ipp orbit of period T_G / 2 run twice: the bridge joins the
// 1-ipp branch to its factor-2 dilation, the case of the paper (Figs. 13-15).
#include <Eigen/Dense>

#include "nsmodal/modal_basis.h"
#include "nsmodal/orbit.h"

namespace nsmodal {

struct Bridge {
  double period = 0.0;       // T_G
  double graze_time = 0.0;   // t_g in (0, T_G)
  Eigen::VectorXd y_graze;   // y_G: the grazing 1-ipp orbit (s = 0)
  Eigen::VectorXd direction; // k
  double s_end = 0.0;        // y(s) admissible for s in [0, s_end]
  // |x_c(S(t_g) k)| / |k|: how far the two NC2 conditions are from coinciding
  // (round-off level on a true bridge).
  double degeneracy_residual = 0.0;
  double energy_min = 0.0, energy_max = 0.0;  // E over [0, s_end]
};

// The bridge at the grazing transition of period `grazing_period` (as found by
// OneImpactTransitions, to ~1e-15). Throws std::invalid_argument if the 1-ipp
// orbit there does not graze (no interior maximum of x_c within 1e-9 d of d).
Bridge BridgeAt(const ModalBasis& b, double grazing_period);

// The potential 2-ipp orbit y(s) of the bridge (times {t_g}, period T_G).
Orbit BridgeOrbit(const ModalBasis& b, const Bridge& bridge, double s);

}  // namespace nsmodal
