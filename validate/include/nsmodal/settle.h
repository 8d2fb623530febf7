#pragma once
// Where a forced motion settles (issue 27: basins of attraction). One
// simulation by the exact integrator from (x0, v0) over `periods` forcing
// periods T_f = 2 pi / w; the state is sampled stroboscopically at the last
// `window` + 1 multiples of T_f. The motion has settled on a periodic
// attractor of n forcing periods (n the smallest from 1 to window / 2) when
// every sample of the last n + 1 repeats the one n periods earlier to `tol`
// of the motion's scale (the largest |component| of the window's samples,
// and at least the least gap): the attractor is then the n stroboscopic
// points, written by its canonical one (the point of least x_1), with the
// impacts of its last n periods (their count, the contacts struck and the
// times, which identify its impact sequence). Otherwise the motion has not
// settled (chaotic, quasi-periodic, or slower than the horizon). A start at
// the forcing phase `phase` (w t_0, on the impact section: on a wall at an
// impact's phase) runs from t_0 = phase / w to the same end, periods T_f.
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "nsmodal/model.h"

namespace nsmodal {

struct SettleOptions {
  int periods = 500;  // forcing periods simulated
  int window = 32;    // stroboscopic samples compared (the longest period found: window / 2)
  double tol = 1e-6;  // relative repetition of the samples
  double phase = 0.0;  // the forcing phase w t_0 of the start, in [0, 2 pi)

  // Throws InputError naming "periods", "window", "tol" or "phase".
  void Validate() const;
};

struct Settled {
  bool settled = false;
  int period = 0;              // n, forcing periods of the attractor (0: not settled)
  Eigen::VectorXd state;       // the canonical stroboscopic state (x, v); empty when not settled
  std::vector<double> impact_times;  // of the last n periods, from the canonical sample's time
  std::vector<int> impact_contacts;  // 0-based, one per impact
  std::vector<double> impact_velocities;  // n_j . v before each impact (> 0: into the wall)
  bool zeno_or_sticking = false;     // the run had a Zeno sequence or a sticking phase
  double repetition = 0.0;     // max |z_k - z_{k-n}| / scale over the last n + 1 samples (n: the period, or window / 2)
  std::string message;         // why not settled (the simulation's status), empty otherwise
};

// Throws InputError for a model with no harmonic force ("forcing.amplitude"),
// a bad initial state (Simulate's errors) or bad options.
Settled Settle(const Model& model, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0, const SettleOptions& options);

}  // namespace nsmodal
