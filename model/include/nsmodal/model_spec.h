#pragma once
// A model as a face gives it: the scene's [system] and [forcing] tables
// (scene.h), the Python module's Model(...) and bar(...) keywords. Every key
// optional, as given; AssembleModel builds and checks the model once for
// both faces, so that the rules (one form of M and K, the contact's default,
// at most one damping form, a harmonic force's amplitude and frequency
// together) are stated in one place.
#include <Eigen/Dense>
#include <optional>
#include <vector>

#include "nsmodal/field_names.h"
#include "nsmodal/model.h"

namespace nsmodal {

struct ModelSpec {
  // M and K: exactly one of a chain (masses and springs), the matrices, or a bar.
  std::optional<std::vector<double>> masses, springs;
  std::optional<Eigen::MatrixXd> mass_matrix, stiffness_matrix;
  std::optional<BarSpec> bar;
  std::optional<double> contact_dof;       // 1-based; default: the last dof
  std::optional<double> gap, restitution;  // both required
  // Damping: at most one form (none: C = 0).
  std::optional<std::vector<double>> rayleigh_damping;  // (a, b): C = a M + b K
  std::optional<std::vector<double>> damping_ratios;    // one per linear mode
  std::optional<Eigen::MatrixXd> damping_matrix;
  // f0 + f cos(w t): the amplitude f and the frequency w come together.
  std::optional<std::vector<double>> forcing_amplitude;
  std::optional<double> forcing_frequency;
  std::optional<std::vector<double>> forcing_constant;
};

// The model of a spec, checked (Validate). Its own checks throw InputError
// naming, through `names`, the key: "form" (not exactly one form of M and K),
// "masses", "springs", "mass_matrix", "stiffness_matrix" (one of a pair
// missing), "contact_dof" (not a whole number of a dof), "gap",
// "restitution" (missing), "damping" (more than one form),
// "rayleigh_damping" (not two coefficients), "forcing.amplitude",
// "forcing.frequency" (one without the other; w not positive). The builders
// (MakeChain, MakeBar, the damping forms) and Validate name the scene's
// fields (system.masses, system.gap, forcing.amplitude, ...) for what they check.
Model AssembleModel(const ModelSpec& spec, const FieldNames& names);

}  // namespace nsmodal
