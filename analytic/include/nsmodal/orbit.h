#pragma once
// A candidate periodic orbit with m impacts per period and its checks
// (paper section 1: NC1, NC2, NC3; potential = NC1 + NC2, admissible = all three).
#include <Eigen/Dense>
#include <limits>
#include <string>
#include <vector>

namespace nsmodal {

// Whether starting an impact sequence at its impact `shift` leaves it as it
// is (j_{i + shift mod m} = j_i for all i): the rotations under which an orbit
// of that sequence is the same orbit. Empty means every impact on contact 1.
inline bool SequenceKeptBy(const std::vector<int>& sequence, int shift) {
  const int m = static_cast<int>(sequence.size());
  for (int i = 0; i < m; ++i) {
    if (sequence[(i + shift) % m] != sequence[i]) return false;
  }
  return true;
}

struct Orbit {
  int impacts = 1;
  double period = 0.0;
  std::vector<double> times;   // t2, ..., tm (t1 = 0 implicit)
  // The contact of each impact (0-based; the impact sequence, issue 24): m
  // entries, all 0 for a one-contact model.
  std::vector<int> sequence;
  Eigen::VectorXd y0;          // scaled modal state just after the impact at t = 0
  Eigen::VectorXd z0;          // physical (x, v) just after the impact at t = 0
  double energy = 0.0;
  double nc2_residual = 0.0;          // max_i |x_c(t_i) - d| / d
  double periodicity_residual = 0.0;  // |z(T) - z(0)| / |z(0)|
  double max_excess = 0.0;            // max over flight of x_c - d at interior maxima (NC3 margin)
  // The other contacts (those not struck at the flight's ends): the largest
  // n_k . x - d_k over every flight (-inf with one contact), and which k.
  double other_excess = -std::numeric_limits<double>::infinity();
  int other_contact = -1;
  bool potential = false;
  bool admissible = false;
  bool degenerate = false;  // NC2 leaves a free parameter (the "bridge", paper section 4)
  std::string reason;       // why it is not potential or not admissible
};

}  // namespace nsmodal
