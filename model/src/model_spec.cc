#include "nsmodal/model_spec.h"

#include <cmath>
#include <memory>
#include <string>

#include "nsmodal/error.h"

namespace nsmodal {

namespace {

// Contact j (0-based) of a list, built and named "contact[j + 1].<key>".
Contact MakeContact(const ContactSpec& c, int j, int n) {
  const std::string at = "contact[" + std::to_string(j + 1) + "].";
  auto dof_index = [&](double v, const std::string& key) {
    if (!(v >= 1 && v <= n) || v != std::floor(v)) {
      throw InputError(at + key, "must name a dof: an integer between 1 and " + std::to_string(n) + ", got " +
                                     FormatValue(v));
    }
    return static_cast<int>(v) - 1;
  };
  const int forms = int(c.dof.has_value()) + int(c.between.has_value()) + int(c.normal.has_value());
  if (forms != 1) {
    throw InputError(at + "dof", "give exactly one of dof (with side), between and normal, got " +
                                     std::to_string(forms));
  }
  if (c.side && !c.dof) throw InputError(at + "side", "goes with dof (the wall above or below that dof)");
  if (!c.gap) throw InputError(at + "gap", "is missing: the distance from rest to the wall");
  if (!c.restitution) {
    throw InputError(at + "restitution",
                     "is missing: the coefficient e of Newton's impact law, 0 <= e <= 1 (1 for periodic orbits)");
  }
  if (c.dof) {
    bool upper = true;
    if (c.side) {
      if (*c.side != "upper" && *c.side != "lower") {
        throw InputError(at + "side", "must be \"upper\" (x <= gap) or \"lower\" (x >= -gap), got \"" + *c.side + "\"");
      }
      upper = *c.side == "upper";
    }
    return DofContact(n, dof_index(*c.dof, "dof"), upper, *c.gap, *c.restitution);
  }
  if (c.between) {
    if (c.between->size() != 2) {
      throw InputError(at + "between", "must be a pair of dofs [a, b] (x_a - x_b <= gap), got " +
                                           std::to_string(c.between->size()) + " entries");
    }
    const int a = dof_index((*c.between)[0], "between"), b = dof_index((*c.between)[1], "between");
    if (a == b) throw InputError(at + "between", "must name two different dofs, got " + std::to_string(a + 1) + " twice");
    return BetweenContact(n, a, b, *c.gap, *c.restitution);
  }
  const std::vector<double>& v = *c.normal;
  return NormalContact(Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())), *c.gap,
                       *c.restitution);
}

}  // namespace

Model AssembleModel(const ModelSpec& s, const FieldNames& names) {
  const bool chain = s.masses || s.springs, matrices = s.mass_matrix || s.stiffness_matrix, bar = s.bar.has_value();
  if (int(chain) + int(matrices) + int(bar) != 1) {
    throw InputError(names("form"), "give exactly one of: masses and springs (a chain), mass_matrix and "
                                    "stiffness_matrix, or bar (a finite-element bar)");
  }
  Model model;
  if (bar) {
    model = MakeBar(*s.bar, s.bar->Dofs() - 1, 1.0, 1.0);  // the contacts are set below
  } else if (chain) {
    if (!s.masses) throw InputError(names("masses"), "is missing");
    if (!s.springs) throw InputError(names("springs"), "is missing");
    model = MakeChain(*s.masses, *s.springs, static_cast<int>(s.masses->size()) - 1, 1.0, 1.0);
  } else {
    if (!s.mass_matrix) throw InputError(names("mass_matrix"), "is missing");
    if (!s.stiffness_matrix) throw InputError(names("stiffness_matrix"), "is missing");
    model.mass = *s.mass_matrix;
    model.stiffness = *s.stiffness_matrix;
  }
  if (s.contacts) {
    if (s.contact_dof || s.gap || s.restitution) {
      throw InputError(names("contact"), "give the contacts either as a list ([[contact]] tables, contacts=[...]) or "
                                         "as the one-contact shorthand (contact_dof, gap, restitution), not both");
    }
    if (s.contacts->empty()) throw InputError(names("contact"), "the list of contacts is empty");
    model.contacts.clear();
    for (std::size_t j = 0; j < s.contacts->size(); ++j) {
      model.contacts.push_back(MakeContact((*s.contacts)[j], static_cast<int>(j), model.dofs()));
    }
  } else {
    int dof = model.dofs() - 1;
    if (const std::optional<double>& c = s.contact_dof) {
      // Range first: casting a non-finite or huge value to an integer is undefined.
      if (!(*c >= 1 && *c <= model.dofs()) || *c != std::floor(*c)) {
        throw InputError(names("contact_dof"), "must be an integer between 1 and " + std::to_string(model.dofs()) +
                                                   ", got " + FormatValue(*c));
      }
      dof = static_cast<int>(*c) - 1;
    }
    // No silent defaults for the obstacle and the impact law: a model that
    // forgot them would be another system.
    if (!s.gap) throw InputError(names("gap"), "is missing: the distance d from rest to the obstacle");
    if (!s.restitution) {
      throw InputError(names("restitution"),
                       "is missing: the coefficient e of Newton's impact law, 0 <= e <= 1 (1 for periodic orbits)");
    }
    model.contacts = {DofContact(model.dofs(), dof, true, *s.gap, *s.restitution)};
    model.contacts.front().shorthand = true;
  }
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
  model.source = std::make_shared<const ModelSource>(ModelSource{s, names});
  return model;
}

}  // namespace nsmodal
