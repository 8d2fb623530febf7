#pragma once
// The vibro-impact model: M xdd + K x = 0 in free flight, one unilateral
// contact x_c <= d (Signorini, paper eq. 1) with a Newton impact law.
//
// Impact law (paper eq. 2b generalised to any SPD M): the impulse acts along
// the contact normal e_c, M (v+ - v-) = e_c * Lambda, with Lambda chosen so that
//   v_c(t+) = -e * v_c(t-),   0 <= e <= 1.
// For a diagonal M this changes v_c only ("other velocities continuous"); for a
// coupled M it is the only choice that conserves energy at e = 1.
#include <Eigen/Dense>
#include <string>
#include <vector>

namespace nsmodal {

struct Model {
  Eigen::MatrixXd mass;       // M, symmetric positive definite, N x N
  Eigen::MatrixXd stiffness;  // K, symmetric positive definite, N x N
  int contact = 0;            // c, 0-based index of the dof that meets the obstacle
  double gap = 1.0;           // d > 0
  double restitution = 1.0;   // e in [0, 1]

  int dofs() const { return static_cast<int>(mass.rows()); }
};

// A chain ground - k1 - m1 - k2 - m2 - ... (the paper's Figure 1 for N = 2).
// springs[0] links the ground to m1, springs[i] links m_i to m_{i+1}.
// Throws InputError naming "system.masses" or "system.springs" on bad values.
Model MakeChain(const std::vector<double>& masses, const std::vector<double>& springs,
                int contact, double gap, double restitution);

// The paper's default system: m1 = m2 = 1, k1 = 0.85, k2 = 2, d = 1, e = 1, c = x2.
Model PaperModel();

// Scales nsmodal honours, checked by Validate and MakeModalBasis:
//   the eigenvalues of M, and those of K, span at most kMaxCondition (a
//   nearly singular matrix leaves no digits in M^-1 K);
//   the linear frequencies span at most kMaxFrequencyRatio (the exact flight
//   and the guaranteed impact search step at the fastest mode's scale over the
//   slowest one's periods);
//   the energy scale K d^2 / 2 lies within [1 / kMaxEnergyScale, kMaxEnergyScale].
//   at most kMaxDofs degrees of freedom (dense N x N matrices and O(N^3)
//   eigen-decompositions: 2000 dofs take 32 MB a matrix and seconds).
inline constexpr int kMaxDofs = 2000;
inline constexpr double kMaxCondition = 1e12;
inline constexpr double kMaxFrequencyRatio = 1e6;
inline constexpr double kMaxEnergyScale = 1e200;

// Checks every field and the scales above; throws InputError naming the field
// ("system.mass_matrix", "system.contact_dof", "system.gap",
// "system.restitution", ...) and the value.
void Validate(const Model& model);

std::string FormatValue(double v);

}  // namespace nsmodal
