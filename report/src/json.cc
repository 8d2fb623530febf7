#include "nsmodal/json.h"

#include <cmath>
#include <stdexcept>
#include <type_traits>
#include <variant>

namespace nsmodal::report {
namespace {

nlohmann::json OrNull(bool present, double v) { return present ? nlohmann::json(v) : nlohmann::json(); }

// The documents' invariant, as the tables' (table.h): a quantity that does
// not exist is null, said where it is set (OrNull); no number is inf or nan
// (nlohmann would dump it as null, silently). Throws std::logic_error naming
// the key: the run fails (exit 1, its results removed) instead of writing it.
void CheckFinite(const nlohmann::json& j, const std::string& where) {
  if (j.is_number_float()) {
    const double v = j.get<double>();
    if (!std::isfinite(v)) {
      throw std::logic_error("internal error: " + where + " holds " + (std::isnan(v) ? "nan" : "inf") +
                             " as a value (a missing quantity must be null); please report it");
    }
  } else if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) CheckFinite(it.value(), where + "." + it.key());
  } else if (j.is_array()) {
    for (std::size_t k = 0; k < j.size(); ++k) CheckFinite(j[k], where + "[" + std::to_string(k) + "]");
  }
}

nlohmann::json Checked(nlohmann::json j, const std::string& document) {
  CheckFinite(j, document);
  return j;
}

}  // namespace

nlohmann::json OrbitJson(const OrbitRecord& record) {
  const Orbit& o = record.orbit;
  const int n = static_cast<int>(o.z0.size() / 2);
  std::vector<double> x(o.z0.data(), o.z0.data() + n), v(o.z0.data() + n, o.z0.data() + 2 * n);
  nlohmann::json j{{"impacts", o.impacts},
                   {"T", o.period},
                   {"impact_times", o.times},
                   {"energy", o.energy},
                   {"potential", o.potential},
                   {"admissible", o.admissible},
                   {"degenerate", o.degenerate},
                   {"periodicity_residual", o.periodicity_residual},
                   {"nc2_residual", o.nc2_residual},
                   {"nc3_margin", OrNull(std::isfinite(o.max_excess), o.max_excess)},
                   {"x", x},
                   {"v", v},
                   {"reason", o.reason}};
  j["t2"] = OrNull(!o.times.empty(), o.times.empty() ? 0.0 : o.times[0]);
  // The contact of each impact, numbered from 1 (issue 24's impact sequence).
  std::vector<int> sequence;
  for (int c : o.sequence) sequence.push_back(c + 1);
  j["sequence"] = sequence;
  if (const auto& s = record.stability) {
    j["stable"] = s->stable;
    j["max_multiplier"] = s->max_modulus;
    j["multipliers"] = nlohmann::json::array();
    for (int k = 0; k < s->multipliers.size(); ++k) {
      j["multipliers"].push_back({s->multipliers[k].real(), s->multipliers[k].imag()});
    }
  }
  return Checked(std::move(j), "orbit");
}

nlohmann::json OrbitsJson(const std::vector<OrbitRecord>& records) {
  nlohmann::json list = nlohmann::json::array();
  for (const OrbitRecord& r : records) list.push_back(OrbitJson(r));
  return nlohmann::json{{"orbits", list}};
}

nlohmann::json ExploreJson(const ExploreReport& r) {
  nlohmann::json j;
  j["impacts"] = r.impacts;
  j["samples"] = r.samples;
  for (auto [k, v] : r.kernel_dimension_histogram) j["kernel_dimension_histogram"][std::to_string(k)] = v;
  j["findings"] = nlohmann::json::array();
  for (const ExploreFinding& f : r.findings) {
    nlohmann::json o = OrbitJson({f.orbit, std::nullopt});
    o["kind"] = f.kind;
    o["kernel_dimension"] = f.kernel_dimension;
    o["grazing_ratio"] = f.grazing_ratio;
    j["findings"].push_back(o);
  }
  j["best_phi_new"] = r.best_phi_new;
  return j;
}

nlohmann::json SimulationJson(const SimulationSummary& s, const Configured<SimulationRequest>& request) {
  const SimulateOptions& opt = request.options.options;
  nlohmann::json j;
  j["integrator"] = ToString(opt.integrator);
  j["status"] = ToString(s.status);
  j["message"] = s.message;
  j["final_time"] = s.final_time;
  j["final_state"] = std::vector<double>(s.final_state.data(), s.final_state.data() + s.final_state.size());
  j["impacts"] = s.impacts;
  j["grazes"] = s.grazes;
  j["zeno_events"] = s.zeno_events;
  j["first_zeno_time"] = OrNull(s.first_zeno_time >= 0.0, s.first_zeno_time);
  j["sticking_phases"] = s.sticking_phases;
  j["sticking_time"] = s.sticking_time;
  // Per contact, contact 1 first.
  j["impacts_per_contact"] = s.impacts_per_contact;
  j["grazes_per_contact"] = s.grazes_per_contact;
  j["zeno_events_per_contact"] = s.zeno_per_contact;
  j["sticking_phases_per_contact"] = s.sticking_per_contact;
  j["initial_energy"] = s.initial_energy;
  j["final_energy"] = s.final_energy;
  j["energy_drift"] = s.energy_drift;
  j["wall_time_s"] = s.wall_time_s;
  j["steps"] = s.steps;
  j["sweep_steps"] = s.sweep_steps;  // exact, from 8 modes on: the impact search's grid steps
  WriteSettings(j, SimulateSettings(), request);
  return Checked(std::move(j), "simulation summary");
}

nlohmann::json TruncationJson(const ModalTruncation& t, double energy) {
  return Checked({{"kept", t.kept},
          {"dofs", t.dofs},
          {"highest_kept_frequency", t.highest_kept_frequency},
          {"lowest_neglected_frequency", OrNull(std::isfinite(t.lowest_neglected_frequency), t.lowest_neglected_frequency)},
          {"residual_flexibility", t.residual_flexibility},
          {"initial_energy", energy},
          {"contact_bound", t.ContactBound(energy)}},
                 "truncation");
}

nlohmann::json ValidationJson(const ValidationReport& report, const std::vector<OrbitValidation>& results,
                              const Configured<ValidationRequest>& request) {
  auto describe = [&](std::size_t i) {
    const OrbitValidation& v = results[i];
    return nlohmann::json{{"T", v.orbit.period},
                          {"t2", OrNull(!v.orbit.times.empty(), v.orbit.times.empty() ? 0.0 : v.orbit.times[0])},
                          {"integrator", ToString(v.integrator)},
                          {"admissible", v.orbit.admissible},
                          {"stable", v.stability.stable},
                          {"deviation_final", OrNull(!v.deviation.empty(), v.deviation.empty() ? 0.0 : v.deviation.back())},
                          {"reason", v.reason}};
  };
  nlohmann::json j;
  j["orbits"] = report.orbits;
  j["periods"] = report.periods;
  j["passed"] = report.passed();
  for (const auto& [integrator, t] : report.integrators) {
    j["integrators"][ToString(integrator)] = {
        {"checked", t.checked}, {"consistent", t.consistent}, {"inconsistent", t.inconsistent}};
  }
  j["inconsistent"] = nlohmann::json::array();
  for (std::size_t i : report.inconsistent) j["inconsistent"].push_back(describe(i));
  for (const auto& [integrator, list] : report.worst_stable) {
    nlohmann::json worst = nlohmann::json::array();
    for (std::size_t i : list) worst.push_back(describe(i));
    j["worst_stable"][ToString(integrator)] = worst;
  }
  j["perturbation"] = {{"relative_size", report.perturbation},
                       {"stable_orbits", report.stable_perturbed},
                       {"stable_worst_amplification", report.stable_worst_amplification},
                       {"unstable_orbits_rated", report.unstable_rated},
                       {"unstable_rate_within_5_percent", report.unstable_within_tolerance},
                       {"unstable_worst_relative_rate_error", report.unstable_worst_rate_error}};
  WriteSettings(j, ValidateSettings(), request);
  return Checked(std::move(j), "validation summary");
}

nlohmann::json SettingValueJson(const SettingValue& value) {
  return std::visit(
      [](const auto& v) -> nlohmann::json {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>) {
          return nullptr;
        } else {
          return v;
        }
      },
      value);
}

namespace {

nlohmann::json TextOrNull(const std::string& s) { return s.empty() ? nlohmann::json() : nlohmann::json(s); }

template <class Options>
void AddReference(nlohmann::json& list, const SettingTable<Options>& table) {
  for (const Setting<Options>& s : table.settings()) {
    const SettingInfo& i = s.info;
    list.push_back({{"name", i.name},
                    {"scene_key", TextOrNull(table.SceneField(i))},
                    {"flag", TextOrNull(i.flag)},
                    {"python", TextOrNull(i.python)},
                    {"kind", ToString(i.kind)},
                    {"default", SettingValueJson(table.Default(s))},
                    {"unit", i.unit},
                    {"doc", i.doc},
                    {"commands", i.commands}});
  }
}

}  // namespace

nlohmann::json SettingsReferenceJson() {
  nlohmann::json list = nlohmann::json::array();
  AddReference(list, SimulateSettings());
  AddReference(list, ValidateSettings());
  return Checked(std::move(list), "settings");
}

void PrintSettingsReference(std::ostream& out) {
  const nlohmann::json list = SettingsReferenceJson();
  auto text = [](const nlohmann::json& v) { return v.is_null() ? std::string("-") : v.is_string() ? v.get<std::string>() : v.dump(); };
  bool first = true;
  for (const nlohmann::json& s : list) {
    if (!first) out << "\n";
    first = false;
    std::string commands;
    for (const auto& c : s["commands"]) commands += (commands.empty() ? "" : ", ") + c.get<std::string>();
    out << s["name"].get<std::string>() << "  (" << s["kind"].get<std::string>()
        << (s["unit"].get<std::string>().empty() ? "" : ", " + s["unit"].get<std::string>()) << ")\n"
        << "  " << s["doc"].get<std::string>() << "\n"
        << "  default " << text(s["default"]) << "; scene key " << text(s["scene_key"]) << "; flag " << text(s["flag"])
        << "; Python keyword " << text(s["python"]) << "; commands: " << commands << "\n";
  }
}

}  // namespace nsmodal::report
