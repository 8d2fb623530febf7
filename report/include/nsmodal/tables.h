#pragma once
// The project's tables, each declared once (table.h): the CSV files of the
// commands and the column arrays of the Python module come from these lists.
#include <Eigen/Dense>

#include "nsmodal/atlas.h"
#include "nsmodal/curve.h"
#include "nsmodal/family_parameter.h"
#include "nsmodal/modal_basis.h"
#include "nsmodal/response.h"
#include "nsmodal/simulate.h"
#include "nsmodal/hdf5.h"
#include "nsmodal/table.h"
#include "nsmodal/truncation.h"
#include "nsmodal/validate.h"
#include "nsmodal/work_precision.h"

namespace nsmodal::report {

// orbits.csv: T,t2,energy,potential,admissible,periodicity_residual,
// nc2_residual,nc3_margin,degenerate,x1..xN,v1..vN,stable,max_multiplier,
// mu1_re,mu1_im..mu2N_re,mu2N_im (t2 missing for one impact; stable and the
// multipliers missing where the sweep's policy computed no stability).
// With a truncation (orbits --modes: the sweep on its kept modes, the
// states mapped back to the N dofs, ToPhysical), one more column,
// neglected_xc_bound: ContactBound of the orbit's energy, the most the
// neglected modes can carry of x_c. The truncation must outlive the columns.
Columns<OrbitRecord> OrbitColumns(int dofs, const ModalTruncation* truncation = nullptr);

// The orbits table of a sweep streamed (StreamSweep: a block of periods in memory
// at a time; the CLI's orbits), written whole or not at all. With a
// truncation the basis is of its model: each state mapped back to the full
// model's dofs (ToPhysical) and the bound's column added (OrbitColumns).
// Returns the counts and, of a 1-ipp sweep, each period's admissibility.
struct SweepWritten {
  long orbits = 0, admissible = 0;
  ZoneScan zones;  // 1 impact only
};
// The table `name` ("orbits") in `format`: NAME.csv or NAME.h5.
SweepWritten WriteSweepTable(const OutputDir& dir, const std::string& name, const AnalysisBasis& b, const PeriodGrid& grid,
                         int impacts, const SweepOptions& options, const ModalTruncation* truncation = nullptr,
                         TableFormat format = TableFormat::kCsv);

// transitions.csv: T,kind,energy,contact (from 1).
Columns<Transition> TransitionColumns();

// The bridges of an atlas: T,t2,energy_min,energy_max,s_begin,s_end,kind.
Columns<Bridge> BridgeColumns();

// validation.csv, one row per orbit and integrator.
Columns<OrbitValidation> ValidationColumns();

// work_precision.csv and grazing.csv of the bench.
Columns<WorkPrecisionRow> WorkPrecisionColumns();
Columns<GrazingRow> GrazingColumns();

// response.csv, one row per point of a response branch:
// w,amplitude,period,impacts,energy,max_xc,impact_velocity,admissible,stable,
// max_multiplier,t_impact,x1..xN,v1..vN,branch,periods,residual: the state
// just after the first impact, at t_impact (m = 0: at the maximum of x_c;
// impact_velocity missing); impact_velocity is the smallest v_c(t_i-).
Columns<ResponseRow> ResponseColumns(int dofs);
// response_points.csv: w,amplitude,kind,energy,branch,max_xc,impact_velocity,
// admissible,stable,max_multiplier.
Columns<SpecialPoint> ResponsePointColumns();
// continuation.csv and continuation_points.csv (issue 26): a column named as
// the followed parameter ("gap", "masses[1]"), then response.csv's, or
// response_points.csv's, columns.
Columns<ResponseRow> ContinuationColumns(int dofs, const std::string& parameter);
Columns<SpecialPoint> ContinuationPointColumns(const std::string& parameter);
// curve.csv (issue 26): both parameters' columns, kind (the followed point,
// or where the curve meets another: curve.h), then response.csv's columns
// with `curve` (1-based) for `branch`, then `condition` (the followed
// defining condition's value: det dH/du, prod (1 + mu), max_interior_gap / d).
// transitions.csv of `continue` on a free scene (issue 26): a column named as
// the parameter, then transitions.csv's (T,kind,energy,contact; kind also
// "bridge", its energy the continuum's lowest), then `track` (1-based: the
// same point followed from value to value).
Columns<FamilyRow> FamilyColumns(const std::string& parameter);
Columns<CurvePoint> CurveColumns(int dofs, const std::string& first, const std::string& second);

// response_validation.csv, one row per orbit and integrator: w,amplitude,
// branch,integrator,admissible,stable,max_multiplier,periods_run,deviation_1,
// deviation_end,measured_growth,predicted_growth,first_period_impacts,
// impact_time_error,max_penetration,consistent,reason.
Columns<ForcedValidationRow> ForcedValidationColumns();

// backbone.csv: the conservative twin's 1-ipp mode beside a response,
// w,T,energy,admissible,stable,max_multiplier,impact_velocity (w = 2 pi / T;
// the impact velocity |v_c| at the impact at t = 0, on `b`'s contacts).
Columns<OrbitRecord> BackboneColumns(const ModalBasis& b);

// A trajectory sample of a simulation: t, x1..xN, v1..vN, energy.
struct Sample {
  double t = 0.0;
  Eigen::VectorXd z;  // physical (x, v)
  double energy = 0.0;
};
// The sample at t of state z = (x, v), with its energy v'Mv/2 + x'Kx/2.
Sample SampleOf(const Model& model, double t, const Eigen::VectorXd& z);
Columns<Sample> TrajectoryColumns(int dofs);
// impacts.csv: t, contact (its number, from 1), x1_before..vN_before, x1_after..vN_after.
Columns<ContactEvent> ImpactColumns(int dofs);

}  // namespace nsmodal::report
