#pragma once
// A scalar parameter of a model, named by its scene key (issue 26): what a
// continuation varies, the others held.
//   frequency                 w of the harmonic force
//   amplitude                 a = max_i |f_i| of the harmonic force (the vector
//                             scaled: its shape kept)
//   gap, restitution          the one contact's (the [system] shorthand, or a
//                             model with one contact)
//   contact[j].gap, contact[j].restitution
//                             contact j's (from 1)
//   masses[i], springs[i]     a chain's (from 1: springs[1] links the ground
//                             to m1)
//   damping_ratios[i]         the modal damping ratio of linear mode i
//   rayleigh_damping[1], rayleigh_damping[2]
//                             a and b of C = a M + b K
// The contact and forcing parameters change the model in place; the others
// rebuild it from the keys it was assembled from (Model::source: a scene's
// [system] table, Python's Model keywords), so that it is checked as a scene
// would be and the damping follows the masses and springs. A value outside
// the valid model (a negative mass, e > 1, a gap <= 0) throws InputError
// naming the scene's field and the value.
//
// Scaling (DESIGN.md): with no force, every orbit of gap d is the orbit of
// gap 1 scaled by d in x and v (the flight is linear, the impact law and the
// conditions x_c(t_i) = d homogeneous): T and the impact times are the same,
// the energy scales by d^2. A gap needs no continuation of a conservative
// model's families: ScaleWithGap says so.
#include <string>

#include "nsmodal/model.h"

namespace nsmodal {

struct ModelParameter {
  enum class Kind { kFrequency, kAmplitude, kGap, kRestitution, kMass, kSpring, kDampingRatio, kRayleigh };
  Kind kind = Kind::kFrequency;
  int index = 0;     // 0-based: the contact, mass, spring, mode or coefficient
  std::string name;  // as written ("masses[1]")
};

// The parameter `name` of `model`. Throws InputError naming `field` (the CLI's
// "--parameter", Python's "parameter") for a name that is not one of the
// list above, an index out of range (masses[3] of two masses), gap or
// restitution of a model with several contacts (name one: contact[j].gap),
// a chain's key of a model that is not a chain, damping_ratios of a model
// without modal damping, amplitude or frequency of a model without a
// harmonic force.
ModelParameter ParseModelParameter(const Model& model, const std::string& name,
                                   const std::string& field = "parameter");

// The model's own value of the parameter.
double ParameterValue(const Model& model, const ModelParameter& p);

// The model with the parameter at `value`, checked (InputError naming the
// scene's field and the value).
Model WithParameter(const Model& model, const ModelParameter& p, double value);

// The scene field a parameter is read from, for messages ("system.masses",
// "contact[2].gap", "forcing.amplitude").
std::string ParameterField(const Model& model, const ModelParameter& p);

}  // namespace nsmodal
