#pragma once
// The settings of a batch validation, declared once (settings.h): the grid,
// the impacts, the periods, the integrators and their tolerances (lifted from
// simulate's table: one declaration each, in [validate] as validate.step),
// the threads. The scene's [validate] table, the `validate` command's flags,
// Python's validate() keywords and summary.json's settings block are made
// from this table.
//
// And the validation they describe, which the CLI and Python both call: the
// potential orbits of the grid, each simulated with each integrator, and the
// verdict.
#include <functional>
#include <vector>

#include "nsmodal/atlas.h"
#include "nsmodal/settings.h"
#include "nsmodal/validate.h"

namespace nsmodal {

struct ValidationRequest {
  ValidateOptions options;
  std::string period;              // FROM:TO:STEP; required
  std::vector<long> impacts{1, 2};  // 1 and/or 2
  std::string sequence;            // "1,2": the contact of each impact (empty: every impact on contact 1)
};

const SettingTable<ValidationRequest>& ValidateSettings();

// A validation ready to run: its options, its grid and impacts, checked,
// with the sweep's and the simulations' work within their limits.
struct ValidationPlan {
  ValidateOptions options;
  PeriodGrid grid;
  std::vector<int> impacts;
  std::vector<int> sequence;  // 0-based contacts of each impact; empty: contact 1
};
// Throws InputError naming each field as the request's origins say.
ValidationPlan PlanValidation(const AnalysisBasis& basis, const Configured<ValidationRequest>& request);

struct GridValidation {
  std::vector<Orbit> orbits;  // the potential orbits of the grid
  std::vector<OrbitValidation> results;
  ValidationReport report;
};
// The potential orbits of the plan's grid, admissible or not, validated.
GridValidation RunValidation(const Model& model, const AnalysisBasis& basis, const ValidationPlan& plan,
                             const std::function<void(long, long)>& progress = {},
                             const FieldNames& names = FieldNames("validate."));

}  // namespace nsmodal
