#pragma once
// The JSON documents of the project: an orbit record (orbit --json, explore
// --json), a simulation's summary.json, a validation batch's summary.json.
// The Python module returns the same documents as dicts.
#include <nlohmann/json.hpp>

#include <ostream>

#include "nsmodal/atlas.h"
#include "nsmodal/explore.h"
#include "nsmodal/settings.h"
#include "nsmodal/simulate_settings.h"
#include "nsmodal/truncation.h"
#include "nsmodal/validate.h"
#include "nsmodal/validate_settings.h"

namespace nsmodal::report {

// impacts, T, impact_times, t2 (null for one impact), sequence (the contact of
// each impact, from 1), energy, potential,
// admissible, degenerate, residuals, nc3_margin (null when not finite), x, v,
// reason, and with stability: stable, max_multiplier, multipliers [[re, im]].
nlohmann::json OrbitJson(const OrbitRecord& record);
// orbit --json, Python's orbit(): {"orbits": [OrbitJson of each]}.
nlohmann::json OrbitsJson(const std::vector<OrbitRecord>& records);

// explore --json: impacts, samples, kernel_dimension_histogram (dimension ->
// count), findings (OrbitJson of each, with kind, kernel_dimension and
// grazing_ratio) and best_phi_new.
nlohmann::json ExploreJson(const ExploreReport& report);

// summary.json of `simulate`: integrator, status, message, final_time,
// final_state, impacts, grazes, zeno_events, first_zeno_time (null: none),
// sticking_phases, sticking_time, impacts_per_contact, grazes_per_contact,
// zeno_events_per_contact, sticking_phases_per_contact (contact 1 first), energies, energy_drift, wall_time_s, steps,
// and the settings blocks (WriteSettings) of the request.
nlohmann::json SimulationJson(const SimulationSummary& s, const Configured<SimulationRequest>& request);

// summary.json's "truncation" of a simulation on the kept modes: kept, dofs,
// highest_kept_frequency, lowest_neglected_frequency (null: none neglected),
// residual_flexibility, initial_energy (J, of the full initial state) and
// contact_bound (ModalTruncation::ContactBound of that energy, m).
nlohmann::json TruncationJson(const ModalTruncation& t, double energy);

// summary.json of `validate`, with the settings blocks of the request.
nlohmann::json ValidationJson(const ValidationReport& report, const std::vector<OrbitValidation>& results,
                              const Configured<ValidationRequest>& request);

// A setting's value: a number, a string, a list, or null (no value).
nlohmann::json SettingValueJson(const SettingValue& value);

// Every summary's settings blocks, made from the table: "settings" (name ->
// value as the run used it) and "settings_source" (name -> default, scene,
// flag or keyword).
template <class Options>
void WriteSettings(nlohmann::json& j, const SettingTable<Options>& table, const Configured<Options>& c) {
  for (const Setting<Options>& s : table.settings()) {
    j["settings"][s.info.name] = SettingValueJson(s.get(c.options));
    j["settings_source"][s.info.name] = ToString(c.origin.at(s.info.name).source);
  }
}

// The settings reference (`nsmodal settings --json`, Python's settings(),
// the docs' reference page): one object per setting of every table, with
// the keys name, scene_key (section.key; null: not in scenes), flag (null:
// none), python (null: none), kind, default (null: none), unit, doc and
// commands.
nlohmann::json SettingsReferenceJson();
// The same for a person: one block per setting.
void PrintSettingsReference(std::ostream& out);

}  // namespace nsmodal::report
