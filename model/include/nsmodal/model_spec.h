#pragma once
// A model as a face gives it: the scene's [system] and [forcing] tables
// (scene.h), the Python module's Model(...) and bar(...) keywords. Every key
// optional, as given; AssembleModel builds and checks the model once for
// both faces, so that the rules (one form of M and K, the contact's default,
// at most one damping form, a harmonic force's amplitude and frequency
// together) are stated in one place.
#include <Eigen/Dense>
#include <optional>
#include <string>
#include <vector>

#include "nsmodal/field_names.h"
#include "nsmodal/model.h"

namespace nsmodal {

// One [[contact]] table (or one dict of Python's contacts=[...]), as given:
// exactly one of dof (with side), between, normal; gap and restitution required.
struct ContactSpec {
  std::optional<double> dof;                  // 1-based
  std::optional<std::string> side;            // "upper" (default) or "lower", with dof
  std::optional<std::vector<double>> between; // [a, b], 1-based: x_a - x_b <= gap
  std::optional<std::vector<double>> normal;  // n: n . x <= gap
  std::optional<double> gap, restitution;
};

struct ModelSpec {
  // M and K: exactly one of a chain (masses and springs), the matrices, or a bar.
  std::optional<std::vector<double>> masses, springs;
  std::optional<Eigen::MatrixXd> mass_matrix, stiffness_matrix;
  std::optional<BarSpec> bar;
  // The contacts: the shorthand for one upper stop (contact_dof, default the
  // last dof; gap and restitution required), or a list of contacts.
  std::optional<double> contact_dof;       // 1-based; default: the last dof
  std::optional<double> gap, restitution;
  std::optional<std::vector<ContactSpec>> contacts;
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
// "restitution" (missing), "contact" (both the shorthand and a list, or an
// empty list), contact[j].<key> for a contact of the list (j from 1: dof,
// side, between, normal, gap, restitution), "damping" (more than one form),
// "rayleigh_damping" (not two coefficients), "forcing.amplitude",
// "forcing.frequency" (one without the other; w not positive). The builders
// (MakeChain, MakeBar, the damping forms) and Validate name the scene's
// fields (system.masses, system.gap, forcing.amplitude, ...) for what they check.
// The model keeps its spec and names (Model::source).
Model AssembleModel(const ModelSpec& spec, const FieldNames& names);

// What a model was assembled from: its keys and how a face names them.
struct ModelSource {
  ModelSpec spec;
  FieldNames names;
};

}  // namespace nsmodal
