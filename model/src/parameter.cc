#include "nsmodal/parameter.h"

#include <cmath>

#include "nsmodal/check.h"
#include "nsmodal/error.h"
#include "nsmodal/model_spec.h"

namespace nsmodal {

namespace {

using Kind = ModelParameter::Kind;

const char* kNames =
    "frequency, amplitude, gap, restitution, contact[j].gap, contact[j].restitution, masses[i], springs[i], "
    "damping_ratios[i], rayleigh_damping[1] or rayleigh_damping[2]";

bool Rebuilt(Kind kind) {
  return kind == Kind::kMass || kind == Kind::kSpring || kind == Kind::kDampingRatio || kind == Kind::kRayleigh;
}

// The spec's vector a rebuilt kind reads (null for the other kinds).
template <class Spec>
auto SpecVector(Spec& spec, Kind kind) -> decltype(&spec.masses) {
  switch (kind) {
    case Kind::kMass: return &spec.masses;
    case Kind::kSpring: return &spec.springs;
    case Kind::kDampingRatio: return &spec.damping_ratios;
    case Kind::kRayleigh: return &spec.rayleigh_damping;
    default: return nullptr;
  }
}

const char* SpecKey(Kind kind) {
  switch (kind) {
    case Kind::kMass: return "masses";
    case Kind::kSpring: return "springs";
    case Kind::kDampingRatio: return "damping_ratios";
    case Kind::kRayleigh: return "rayleigh_damping";
    default: return "";
  }
}

}  // namespace

ModelParameter ParseModelParameter(const Model& model, const std::string& name, const std::string& field) {
  // key, then [index] (1 to 6 digits), then .member; keys and members are
  // lower-case words. (By hand: GCC 12 warns falsely inside std::regex.)
  auto word = [&](std::size_t& at) {
    const std::size_t from = at;
    while (at < name.size() && ((name[at] >= 'a' && name[at] <= 'z') || name[at] == '_')) ++at;
    return name.substr(from, at - from);
  };
  std::size_t at = 0;
  const std::string key = word(at);
  bool indexed = false, ok = !key.empty();
  int index = 0;
  if (ok && at < name.size() && name[at] == '[') {
    const std::size_t from = ++at;
    while (at < name.size() && name[at] >= '0' && name[at] <= '9' && at - from < 6) index = 10 * index + (name[at++] - '0');
    ok = at > from && at < name.size() && name[at] == ']';
    ++at;
    indexed = true;
  }
  std::string member;
  if (ok && at < name.size() && name[at] == '.') {
    ++at;
    member = word(at);
    ok = !member.empty();
  }
  if (!ok || at != name.size()) {
    throw InputError(field, "'" + name + "' is not a parameter: name one of " + kNames);
  }
  ModelParameter p;
  p.name = name;
  auto need_index = [&](bool want) {
    if (indexed != want || (want && index < 1)) {
      throw InputError(field, "'" + name + "': " + (want ? key + "[i] takes an index from 1" : key + " takes no index"));
    }
  };
  auto in_range = [&](int count, const std::string& what) {
    if (index > count) {
      throw InputError(field, "'" + name + "': the model has " + std::to_string(count) + " " + what + ", numbered from 1");
    }
  };
  if ((key == "frequency" || key == "amplitude") && member.empty()) {
    need_index(false);
    if (!model.forcing.HasHarmonic()) {
      throw InputError(field, "'" + name + "': the model has no harmonic force ([forcing] amplitude and frequency)");
    }
    p.kind = key == "frequency" ? Kind::kFrequency : Kind::kAmplitude;
    return p;
  }
  if ((key == "gap" || key == "restitution") && member.empty()) {
    need_index(false);
    if (model.NumContacts() != 1) {
      throw InputError(field, "'" + name + "': the model has " + std::to_string(model.NumContacts()) +
                                  " contacts: name one, contact[j]." + key);
    }
    p.kind = key == "gap" ? Kind::kGap : Kind::kRestitution;
    return p;
  }
  if (key == "contact" && (member == "gap" || member == "restitution")) {
    need_index(true);
    in_range(model.NumContacts(), "contacts");
    p.kind = member == "gap" ? Kind::kGap : Kind::kRestitution;
    p.index = index - 1;
    return p;
  }
  for (Kind kind : {Kind::kMass, Kind::kSpring, Kind::kDampingRatio, Kind::kRayleigh}) {
    if (key != SpecKey(kind) || !member.empty()) continue;
    need_index(true);
    const std::optional<std::vector<double>>* values = model.source ? SpecVector(model.source->spec, kind) : nullptr;
    if (values == nullptr || !values->has_value()) {
      throw InputError(field, "'" + name + "': the model carries no " + key + " key" +
                                  (kind == Kind::kMass || kind == Kind::kSpring
                                       ? " (not a chain of masses and springs, or built from matrices, in code, or "
                                         "unpickled)"
                                       : ""));
    }
    in_range(static_cast<int>((*values)->size()), key == "rayleigh_damping" ? "coefficients (a, b)" : key);
    p.kind = kind;
    p.index = index - 1;
    return p;
  }
  throw InputError(field, "'" + name + "' is not a parameter: name one of " + kNames);
}

double ParameterValue(const Model& model, const ModelParameter& p) {
  switch (p.kind) {
    case Kind::kFrequency: return model.forcing.frequency;
    case Kind::kAmplitude: return model.ForceAmplitude().cwiseAbs().maxCoeff();
    case Kind::kGap: return model.contacts.at(static_cast<std::size_t>(p.index)).gap;
    case Kind::kRestitution: return model.contacts.at(static_cast<std::size_t>(p.index)).restitution;
    default: break;
  }
  NSMODAL_CHECK(model.source != nullptr);
  const std::optional<std::vector<double>>* values = SpecVector(model.source->spec, p.kind);
  NSMODAL_CHECK(values != nullptr && values->has_value());
  return (*values)->at(static_cast<std::size_t>(p.index));
}

std::string ParameterField(const Model& model, const ModelParameter& p) {
  switch (p.kind) {
    case Kind::kFrequency: return "forcing.frequency";
    case Kind::kAmplitude: return "forcing.amplitude";
    case Kind::kGap:
    case Kind::kRestitution: {
      const std::size_t j = static_cast<std::size_t>(p.index);
      return ContactField(model.contacts.at(j), p.index, p.kind == Kind::kGap ? "gap" : "restitution");
    }
    default: return std::string("system.") + SpecKey(p.kind);
  }
}

Model WithParameter(const Model& model, const ModelParameter& p, double value) {
  if (model.source) {
    // Through the keys: the model is assembled and checked as a scene's, and
    // its source stays the keys of the model it is (a second parameter
    // changed later keeps this one's value).
    ModelSpec spec = model.source->spec;
    switch (p.kind) {
      case Kind::kFrequency: spec.forcing_frequency = value; break;
      case Kind::kAmplitude: {
        NSMODAL_CHECK(spec.forcing_amplitude.has_value());
        const double a = ParameterValue(model, p);
        NSMODAL_CHECK(a > 0.0);
        for (double& f : *spec.forcing_amplitude) f *= value / a;
        break;
      }
      case Kind::kGap:
      case Kind::kRestitution:
        if (spec.contacts) {
          ContactSpec& c = spec.contacts->at(static_cast<std::size_t>(p.index));
          (p.kind == Kind::kGap ? c.gap : c.restitution) = value;
        } else {
          NSMODAL_CHECK(p.index == 0);
          (p.kind == Kind::kGap ? spec.gap : spec.restitution) = value;
        }
        break;
      default: (*SpecVector(spec, p.kind))->at(static_cast<std::size_t>(p.index)) = value;
    }
    return AssembleModel(spec, model.source->names);
  }
  NSMODAL_CHECK(!Rebuilt(p.kind));  // (ParseModelParameter refuses them without keys)
  Model out = model;
  switch (p.kind) {
    case Kind::kFrequency: out.forcing.frequency = value; break;
    case Kind::kAmplitude: {
      const double a = ParameterValue(model, p);
      NSMODAL_CHECK(a > 0.0);
      out.forcing.amplitude *= value / a;
      break;
    }
    case Kind::kGap: out.contacts.at(static_cast<std::size_t>(p.index)).gap = value; break;
    case Kind::kRestitution: out.contacts.at(static_cast<std::size_t>(p.index)).restitution = value; break;
    default: break;
  }
  if (!std::isfinite(value)) throw InputError(ParameterField(model, p), "must be finite, got " + FormatValue(value));
  Validate(out);
  return out;
}

}  // namespace nsmodal
