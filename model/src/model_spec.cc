#include "nsmodal/model_spec.h"

#include <cmath>
#include <string>

#include "nsmodal/error.h"

namespace nsmodal {

Model AssembleModel(const ModelSpec& s, const FieldNames& names) {
  const bool chain = s.masses || s.springs, matrices = s.mass_matrix || s.stiffness_matrix, bar = s.bar.has_value();
  if (int(chain) + int(matrices) + int(bar) != 1) {
    throw InputError(names("form"), "give exactly one of: masses and springs (a chain), mass_matrix and "
                                    "stiffness_matrix, or bar (a finite-element bar)");
  }
  Model model;
  if (bar) {
    model = MakeBar(*s.bar, s.bar->Dofs() - 1, 1.0, 1.0);  // contact on the last node unless contact_dof says otherwise
  } else if (chain) {
    if (!s.masses) throw InputError(names("masses"), "is missing");
    if (!s.springs) throw InputError(names("springs"), "is missing");
    model = MakeChain(*s.masses, *s.springs, static_cast<int>(s.masses->size()) - 1, 1.0, 1.0);
  } else {
    if (!s.mass_matrix) throw InputError(names("mass_matrix"), "is missing");
    if (!s.stiffness_matrix) throw InputError(names("stiffness_matrix"), "is missing");
    model.mass = *s.mass_matrix;
    model.stiffness = *s.stiffness_matrix;
    model.contact = model.dofs() - 1;
  }
  if (const std::optional<double>& c = s.contact_dof) {
    // Range first: casting a non-finite or huge value to an integer is undefined.
    if (!(*c >= 1 && *c <= model.dofs()) || *c != std::floor(*c)) {
      throw InputError(names("contact_dof"), "must be an integer between 1 and " + std::to_string(model.dofs()) +
                                                 ", got " + FormatValue(*c));
    }
    model.contact = static_cast<int>(*c) - 1;
  }
  // No silent defaults for the obstacle and the impact law: a model that
  // forgot them would be another system.
  if (!s.gap) throw InputError(names("gap"), "is missing: the distance d from rest to the obstacle");
  model.gap = *s.gap;
  if (!s.restitution) {
    throw InputError(names("restitution"),
                     "is missing: the coefficient e of Newton's impact law, 0 <= e <= 1 (1 for periodic orbits)");
  }
  model.restitution = *s.restitution;
  Validate(model);  // M and K first: the damping forms are built from them
  if ((s.rayleigh_damping ? 1 : 0) + (s.damping_ratios ? 1 : 0) + (s.damping_matrix ? 1 : 0) > 1) {
    throw InputError(names("damping"), "give at most one of rayleigh_damping, damping_ratios and damping_matrix");
  }
  if (const auto& ab = s.rayleigh_damping) {
    if (ab->size() != 2) {
      throw InputError(names("rayleigh_damping"),
                       "must be [a, b] (C = a M + b K), got " + std::to_string(ab->size()) + " entries");
    }
    model.damping = RayleighDamping(model.mass, model.stiffness, (*ab)[0], (*ab)[1]);
  }
  if (s.damping_ratios) model.damping = ModalDamping(model.mass, model.stiffness, *s.damping_ratios);
  if (s.damping_matrix) model.damping = *s.damping_matrix;
  auto vector = [](const std::vector<double>& v) {
    return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())).eval();
  };
  if (s.forcing_amplitude && !s.forcing_frequency) {
    throw InputError(names("forcing.frequency"), "is missing: the angular frequency w (rad/s) of f cos(w t)");
  }
  if (s.forcing_frequency && !s.forcing_amplitude) {
    throw InputError(names("forcing.amplitude"), "is missing: the force amplitude f on each dof");
  }
  if (s.forcing_amplitude) model.forcing.amplitude = vector(*s.forcing_amplitude);
  if (s.forcing_constant) model.forcing.constant = vector(*s.forcing_constant);
  if (s.forcing_frequency) {
    model.forcing.frequency = *s.forcing_frequency;
    if (!(model.forcing.frequency > 0.0)) {
      throw InputError(names("forcing.frequency"), "must be positive, got " + FormatValue(model.forcing.frequency));
    }
  }
  Validate(model);
  return model;
}

}  // namespace nsmodal
