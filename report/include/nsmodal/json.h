#pragma once
// The JSON documents of the project: an orbit record (orbit --json, explore
// --json), a simulation's summary.json, a validation batch's summary.json.
// The Python module returns the same documents as dicts.
#include <nlohmann/json.hpp>

#include "nsmodal/atlas.h"
#include "nsmodal/simulate.h"
#include "nsmodal/truncation.h"
#include "nsmodal/validate.h"

namespace nsmodal::report {

// impacts, T, impact_times, t2 (null for one impact), energy, potential,
// admissible, degenerate, residuals, nc3_margin (null when not finite), x, v,
// reason, and with stability: stable, max_multiplier, multipliers [[re, im]].
nlohmann::json OrbitJson(const OrbitRecord& record);

// summary.json of `simulate`: integrator, status, message, final_time,
// final_state, impacts, grazes, zeno_events, first_zeno_time (null: none),
// sticking_phases, sticking_time, energies, energy_drift, wall_time_s, steps,
// settings.
nlohmann::json SimulationJson(const SimulationSummary& s, const SimulateOptions& options);

// summary.json's "truncation" of a simulation on the kept modes: kept, dofs,
// highest_kept_frequency, lowest_neglected_frequency (null: none neglected),
// residual_flexibility, initial_energy (J, of the full initial state) and
// contact_bound (ModalTruncation::ContactBound of that energy, m).
nlohmann::json TruncationJson(const ModalTruncation& t, double energy);

// summary.json of `validate`.
nlohmann::json ValidationJson(const ValidationReport& report, const std::vector<OrbitValidation>& results);

}  // namespace nsmodal::report
