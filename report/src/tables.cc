#include "nsmodal/tables.h"

#include <cmath>

#include "nsmodal/flow.h"

namespace nsmodal::report {
namespace {

using K = ColumnKind;

template <class Row>
void AddState(Columns<Row>& cols, int dofs, const std::string& suffix,
              std::function<const Eigen::VectorXd&(const Row&)> state) {
  for (int i = 0; i < 2 * dofs; ++i) {
    // (appended, not `+`: GCC 12 warns falsely on a chain of + here, -Wrestrict)
    std::string name = i < dofs ? "x" : "v";
    name.append(std::to_string(i % dofs + 1)).append(suffix);
    cols.push_back({name, K::kReal, [state, i](const Row& r) -> Cell { return state(r)[i]; }});
  }
}

Cell OrMissing(bool present, double v) { return present ? Cell(v) : Cell(); }

// A quantity whose library value is +-inf where it does not exist (said at
// each use): missing there, never written as inf.
Cell FiniteOrMissing(double v) { return OrMissing(std::isfinite(v), v); }

}  // namespace

Columns<OrbitRecord> OrbitColumns(int dofs, const ModalTruncation* truncation) {
  Columns<OrbitRecord> c{
      {"T", K::kReal, [](const OrbitRecord& r) -> Cell { return r.orbit.period; }},
      {"t2", K::kReal,
       [](const OrbitRecord& r) { return OrMissing(!r.orbit.times.empty(), r.orbit.times.empty() ? 0.0 : r.orbit.times[0]); }},
      {"energy", K::kReal, [](const OrbitRecord& r) -> Cell { return r.orbit.energy; }},
      {"potential", K::kBool, [](const OrbitRecord& r) -> Cell { return r.orbit.potential; }},
      {"admissible", K::kBool, [](const OrbitRecord& r) -> Cell { return r.orbit.admissible; }},
      {"periodicity_residual", K::kReal, [](const OrbitRecord& r) -> Cell { return r.orbit.periodicity_residual; }},
      {"nc2_residual", K::kReal, [](const OrbitRecord& r) -> Cell { return r.orbit.nc2_residual; }},
      // -inf when no flight has an interior maximum of x_c: no margin.
      {"nc3_margin", K::kReal, [](const OrbitRecord& r) { return FiniteOrMissing(r.orbit.max_excess); }},
      {"degenerate", K::kBool, [](const OrbitRecord& r) -> Cell { return r.orbit.degenerate; }},
  };
  AddState<OrbitRecord>(c, dofs, "", [](const OrbitRecord& r) -> const Eigen::VectorXd& { return r.orbit.z0; });
  c.push_back({"stable", K::kBool, [](const OrbitRecord& r) { return r.stability ? Cell(r.stability->stable) : Cell(); }});
  c.push_back({"max_multiplier", K::kReal,
               [](const OrbitRecord& r) { return OrMissing(r.stability.has_value(), r.stability ? r.stability->max_modulus : 0.0); }});
  for (int k = 0; k < 2 * dofs; ++k) {
    for (int part = 0; part < 2; ++part) {
      c.push_back({"mu" + std::to_string(k + 1) + (part ? "_im" : "_re"), K::kReal, [k, part](const OrbitRecord& r) {
                     // Absent where not computed, or not located (a verdict-only spectrum).
                     if (!r.stability || k >= r.stability->multipliers.size()) return Cell();
                     const std::complex<double> mu = r.stability->multipliers[k];
                     return Cell(part ? mu.imag() : mu.real());
                   }});
    }
  }
  if (truncation) {
    c.push_back({"neglected_xc_bound", K::kReal,
                 [truncation](const OrbitRecord& r) -> Cell { return truncation->ContactBound(r.orbit.energy); }});
  }
  return c;
}

SweepWritten WriteSweepTable(const OutputDir& dir, const std::string& name, const AnalysisBasis& b, const PeriodGrid& grid,
                         int impacts, const SweepOptions& options, const ModalTruncation* truncation,
                         TableFormat format) {
  TableWriter<OrbitRecord> out(dir, name, OrbitColumns(truncation ? truncation->dofs : b.n, truncation), format);
  SweepWritten counts;
  StreamSweep(b, grid, impacts, options, [&](double period, std::vector<OrbitRecord>& list) {
    if (truncation) ToPhysical(*truncation, list);
    for (const OrbitRecord& r : list) {
      out.Append(r);
      ++counts.orbits;
      counts.admissible += r.orbit.admissible;
    }
    if (impacts == 1) counts.zones.Add(period, list);
  });
  out.Commit();
  return counts;
}

Columns<ResponseRow> ResponseColumns(int dofs) {
  using R = ResponseRow;
  Columns<R> c{
      {"w", K::kReal, [](const R& r) -> Cell { return r.orbit.frequency; }},
      {"amplitude", K::kReal, [](const R& r) -> Cell { return r.orbit.amplitude; }},
      {"period", K::kReal, [](const R& r) -> Cell { return r.orbit.period; }},
      {"impacts", K::kInteger, [](const R& r) -> Cell { return static_cast<long>(r.orbit.impacts); }},
      {"energy", K::kReal, [](const R& r) -> Cell { return r.orbit.energy; }},
      {"max_xc", K::kReal, [](const R& r) -> Cell { return r.orbit.max_xc; }},
      {"impact_velocity", K::kReal,
       [](const R& r) { return OrMissing(r.orbit.impacts > 0, r.orbit.min_impact_velocity); }},
      {"admissible", K::kBool, [](const R& r) -> Cell { return r.orbit.admissible; }},
      {"stable", K::kBool, [](const R& r) -> Cell { return r.orbit.stable; }},
      {"max_multiplier", K::kReal, [](const R& r) -> Cell { return r.orbit.max_multiplier; }},
      {"t_impact", K::kReal, [](const R& r) -> Cell { return r.orbit.times.front(); }},
  };
  AddState<R>(c, dofs, "", [](const R& r) -> const Eigen::VectorXd& { return r.orbit.after.front(); });
  c.push_back({"branch", K::kInteger, [](const R& r) -> Cell { return static_cast<long>(r.branch); }});
  c.push_back({"periods", K::kInteger, [](const R& r) -> Cell { return static_cast<long>(r.orbit.periods); }});
  c.push_back({"residual", K::kReal, [](const R& r) -> Cell { return r.orbit.residual; }});
  return c;
}

Columns<ResponseRow> ContinuationColumns(int dofs, const std::string& parameter) {
  Columns<ResponseRow> c{{parameter, K::kReal, [](const ResponseRow& r) -> Cell { return r.parameter; }}};
  const Columns<ResponseRow> rest = ResponseColumns(dofs);
  c.insert(c.end(), rest.begin(), rest.end());
  return c;
}

Columns<SpecialPoint> ContinuationPointColumns(const std::string& parameter) {
  Columns<SpecialPoint> c{{parameter, K::kReal, [](const SpecialPoint& p) -> Cell { return p.parameter; }}};
  const Columns<SpecialPoint> rest = ResponsePointColumns();
  c.insert(c.end(), rest.begin(), rest.end());
  return c;
}

Columns<FamilyRow> FamilyColumns(const std::string& parameter) {
  using R = FamilyRow;
  return {{parameter, K::kReal, [](const R& r) -> Cell { return r.parameter; }},
          {"T", K::kReal, [](const R& r) -> Cell { return r.period; }},
          {"kind", K::kText, [](const R& r) -> Cell { return r.kind; }},
          {"energy", K::kReal, [](const R& r) { return FiniteOrMissing(r.energy); }},
          {"contact", K::kInteger, [](const R& r) -> Cell { return long{r.contact + 1}; }},
          {"track", K::kInteger, [](const R& r) -> Cell { return static_cast<long>(r.track + 1); }}};
}

Columns<CurvePoint> CurveColumns(int dofs, const std::string& first, const std::string& second) {
  using P = CurvePoint;
  Columns<P> c{{first, K::kReal, [](const P& p) -> Cell { return p.first; }},
               {second, K::kReal, [](const P& p) -> Cell { return p.second; }},
               {"kind", K::kText, [](const P& p) -> Cell { return p.kind; }}};
  for (Column<ResponseRow>& r : ResponseColumns(dofs)) {
    const bool branch = r.name == "branch";
    c.push_back({branch ? "curve" : r.name, r.kind, [cell = std::move(r.cell)](const P& p) {
                   return cell(ResponseRow{p.curve + 1, p.orbit, 0.0});
                 }});
  }
  c.push_back({"condition", K::kReal, [](const P& p) { return Real(p.condition); }});
  return c;
}

Columns<SpecialPoint> ResponsePointColumns() {
  using P = SpecialPoint;
  return {{"w", K::kReal, [](const P& p) -> Cell { return p.orbit.frequency; }},
          {"amplitude", K::kReal, [](const P& p) -> Cell { return p.orbit.amplitude; }},
          {"kind", K::kText, [](const P& p) -> Cell { return ToString(p.kind); }},
          {"energy", K::kReal, [](const P& p) -> Cell { return p.orbit.energy; }},
          {"branch", K::kInteger, [](const P& p) -> Cell { return static_cast<long>(p.branch + 1); }},
          {"max_xc", K::kReal, [](const P& p) -> Cell { return p.orbit.max_xc; }},
          {"impact_velocity", K::kReal,
           [](const P& p) { return OrMissing(p.orbit.impacts > 0, p.orbit.min_impact_velocity); }},
          {"admissible", K::kBool, [](const P& p) -> Cell { return p.orbit.admissible; }},
          {"stable", K::kBool, [](const P& p) -> Cell { return p.orbit.stable; }},
          {"max_multiplier", K::kReal, [](const P& p) -> Cell { return p.orbit.max_multiplier; }}};
}

Columns<ForcedValidationRow> ForcedValidationColumns() {
  using R = ForcedValidationRow;
  return {
      {"w", K::kReal, [](const R& r) -> Cell { return r.v.orbit.frequency; }},
      {"amplitude", K::kReal, [](const R& r) -> Cell { return r.v.orbit.amplitude; }},
      {"branch", K::kInteger, [](const R& r) -> Cell { return static_cast<long>(r.branch); }},
      {"integrator", K::kText, [](const R& r) -> Cell { return ToString(r.v.integrator); }},
      {"admissible", K::kBool, [](const R& r) -> Cell { return r.v.orbit.admissible; }},
      {"stable", K::kBool, [](const R& r) -> Cell { return r.v.orbit.stable; }},
      {"max_multiplier", K::kReal, [](const R& r) -> Cell { return r.v.orbit.max_multiplier; }},
      {"periods_run", K::kInteger, [](const R& r) -> Cell { return static_cast<long>(r.v.deviation.size()); }},
      {"deviation_1", K::kReal, [](const R& r) { return OrMissing(!r.v.deviation.empty(), r.v.deviation.empty() ? 0.0 : r.v.deviation.front()); }},
      {"deviation_end", K::kReal, [](const R& r) { return OrMissing(!r.v.deviation.empty(), r.v.deviation.empty() ? 0.0 : r.v.deviation.back()); }},
      {"measured_growth", K::kReal, [](const R& r) -> Cell { return r.v.measured_growth; }},
      {"predicted_growth", K::kReal,
       [](const R& r) { return OrMissing(r.v.orbit.max_multiplier > 0.0, std::log(r.v.orbit.max_multiplier)); }},
      {"first_period_impacts", K::kInteger, [](const R& r) -> Cell { return r.v.first_period_impacts; }},
      {"impact_time_error", K::kReal, [](const R& r) { return Real(r.v.impact_time_error); }},
      {"max_penetration", K::kReal, [](const R& r) -> Cell { return r.v.max_penetration; }},
      {"consistent", K::kBool, [](const R& r) -> Cell { return r.v.consistent; }},
      {"reason", K::kText, [](const R& r) -> Cell { return r.v.reason; }},
  };
}

Columns<OrbitRecord> BackboneColumns(const ModalBasis& b) {
  using R = OrbitRecord;
  // |v_c| just after the impact at t = 0, on the contact struck: the impact
  // velocity (e = 1: the same before), as the response's.
  auto impact_velocity = [&b](const R& r) -> Cell {
    const int j = r.orbit.sequence.empty() ? 0 : r.orbit.sequence.front();
    return std::abs(ContactVelocity(b, b.contacts[static_cast<std::size_t>(j)], r.orbit.y0));
  };
  return {{"w", K::kReal, [](const R& r) -> Cell { return 2.0 * M_PI / r.orbit.period; }},
          {"T", K::kReal, [](const R& r) -> Cell { return r.orbit.period; }},
          {"energy", K::kReal, [](const R& r) -> Cell { return r.orbit.energy; }},
          {"admissible", K::kBool, [](const R& r) -> Cell { return r.orbit.admissible; }},
          {"stable", K::kBool, [](const R& r) { return r.stability ? Cell(r.stability->stable) : Cell(); }},
          {"max_multiplier", K::kReal,
           [](const R& r) { return OrMissing(r.stability.has_value(), r.stability ? r.stability->max_modulus : 0.0); }},
          {"impact_velocity", K::kReal, impact_velocity}};
}

Columns<Transition> TransitionColumns() {
  return {{"T", K::kReal, [](const Transition& t) -> Cell { return t.period; }},
          {"kind", K::kText, [](const Transition& t) -> Cell { return ToString(t.kind); }},
          // inf at a singular transition (the energy diverges: no orbit there).
          {"energy", K::kReal, [](const Transition& t) { return FiniteOrMissing(t.energy); }},
          // The contact concerned, from 1 (a grazing: the contact whose gap closes).
          {"contact", K::kInteger, [](const Transition& t) -> Cell { return long{t.contact + 1}; }}};
}

Columns<Bridge> BridgeColumns() {
  return {{"T", K::kReal, [](const Bridge& b) -> Cell { return b.period; }},
          {"t2", K::kReal, [](const Bridge& b) -> Cell { return b.t2; }},
          {"energy_min", K::kReal, [](const Bridge& b) -> Cell { return b.energy_min; }},
          {"energy_max", K::kReal, [](const Bridge& b) -> Cell { return b.energy_max; }},
          {"s_begin", K::kReal, [](const Bridge& b) -> Cell { return b.s_begin; }},
          {"s_end", K::kReal, [](const Bridge& b) -> Cell { return b.s_end; }},
          {"kind", K::kText, [](const Bridge& b) -> Cell {
             return std::string(b.kind == BridgeKind::kGrazing ? "grazing" : "period-doubling");
           }}};
}

Columns<OrbitValidation> ValidationColumns() {
  using V = OrbitValidation;
  auto deviation = [](int k) {
    return [k](const V& v) { return OrMissing(k >= 1 && k <= static_cast<int>(v.deviation.size()), v.DeviationAt(k)); };
  };
  return {
      {"T", K::kReal, [](const V& v) -> Cell { return v.orbit.period; }},
      {"t2", K::kReal, [](const V& v) { return OrMissing(!v.orbit.times.empty(), v.orbit.times.empty() ? 0.0 : v.orbit.times[0]); }},
      {"impacts_per_period", K::kInteger, [](const V& v) -> Cell { return static_cast<long>(v.orbit.impacts); }},
      {"integrator", K::kText, [](const V& v) -> Cell { return ToString(v.integrator); }},
      {"admissible", K::kBool, [](const V& v) -> Cell { return v.orbit.admissible; }},
      {"stable", K::kBool, [](const V& v) -> Cell { return v.stability.stable; }},
      {"max_multiplier", K::kReal, [](const V& v) -> Cell { return v.stability.max_modulus; }},
      {"predicted_growth", K::kReal, [](const V& v) -> Cell { return v.stability.growth_per_period; }},
      {"measured_growth", K::kReal, [](const V& v) -> Cell { return v.measured_growth; }},
      {"deviation_1", K::kReal, deviation(1)},
      {"deviation_10", K::kReal, deviation(10)},
      {"deviation_100", K::kReal, deviation(100)},
      {"deviation_final", K::kReal, [](const V& v) { return OrMissing(!v.deviation.empty(), v.deviation.empty() ? 0.0 : v.deviation.back()); }},
      {"periods_run", K::kInteger, [](const V& v) -> Cell { return static_cast<long>(v.deviation.size()); }},
      {"impacts", K::kInteger, [](const V& v) -> Cell { return v.impacts; }},
      {"first_period_impacts", K::kInteger, [](const V& v) -> Cell { return v.first_period_impacts; }},
      {"impact_time_error", K::kReal, [](const V& v) { return Real(v.impact_time_error); }},
      {"max_penetration", K::kReal, [](const V& v) -> Cell { return v.max_penetration; }},
      {"manifold_distance", K::kReal, [](const V& v) { return OrMissing(v.manifold_distance >= 0.0, v.manifold_distance); }},
      {"perturbed_manifold_distance", K::kReal,
       [](const V& v) { return OrMissing(v.perturbed_manifold_distance >= 0.0, v.perturbed_manifold_distance); }},
      {"perturbed_amplification", K::kReal,
       [](const V& v) { return OrMissing(v.perturbed_periods >= 0, v.perturbed_amplification); }},
      {"perturbed_growth", K::kReal, [](const V& v) { return OrMissing(v.perturbed_periods >= 0, v.perturbed_growth); }},
      // A count that may be missing: real-valued (written as an integer) so that
      // the Python column can hold NaN.
      {"perturbed_periods", K::kReal,
       [](const V& v) { return OrMissing(v.perturbed_periods >= 0, static_cast<double>(v.perturbed_periods)); }},
      {"energy_drift", K::kReal, [](const V& v) -> Cell { return v.energy_drift; }},
      {"wall_time_s", K::kReal, [](const V& v) -> Cell { return v.wall_time_s; }},
      {"consistent", K::kBool, [](const V& v) -> Cell { return v.consistent; }},
      {"reason", K::kText, [](const V& v) -> Cell { return v.reason; }},
  };
}

Columns<WorkPrecisionRow> WorkPrecisionColumns() {
  using R = WorkPrecisionRow;
  return {{"case", K::kText, [](const R& r) -> Cell { return r.case_name; }},
          {"integrator", K::kText, [](const R& r) -> Cell { return r.integrator; }},
          {"setting", K::kText, [](const R& r) -> Cell { return r.setting; }},
          // inf when the run stopped early: no final state to compare.
          {"error", K::kReal, [](const R& r) { return FiniteOrMissing(r.error); }},
          {"cpu_s", K::kReal, [](const R& r) -> Cell { return r.cpu_s; }},
          {"impacts", K::kInteger, [](const R& r) -> Cell { return r.impacts; }},
          {"steps", K::kInteger, [](const R& r) -> Cell { return r.steps; }},
          {"expected_impacts", K::kInteger, [](const R& r) -> Cell { return r.expected_impacts; }}};
}

Columns<GrazingRow> GrazingColumns() {
  using R = GrazingRow;
  return {{"delta", K::kReal, [](const R& r) -> Cell { return r.delta; }},
          {"side", K::kText, [](const R& r) -> Cell { return r.side; }},
          // -inf when the orbit's flights have no interior maximum of x_c.
          {"clearance", K::kReal, [](const R& r) { return FiniteOrMissing(r.clearance); }},
          {"integrator", K::kText, [](const R& r) -> Cell { return r.integrator; }},
          {"setting", K::kText, [](const R& r) -> Cell { return r.setting; }},
          {"impacts", K::kInteger, [](const R& r) -> Cell { return r.impacts; }},
          {"expected_impacts", K::kInteger, [](const R& r) -> Cell { return r.expected_impacts; }}};
}

Sample SampleOf(const Model& model, double t, const Eigen::VectorXd& z) {
  const int n = model.dofs();
  const double energy = 0.5 * z.tail(n).dot(model.mass * z.tail(n)) + 0.5 * z.head(n).dot(model.stiffness * z.head(n));
  return {t, z, energy};
}

Columns<Sample> TrajectoryColumns(int dofs) {
  Columns<Sample> c{{"t", K::kReal, [](const Sample& s) -> Cell { return s.t; }}};
  AddState<Sample>(c, dofs, "", [](const Sample& s) -> const Eigen::VectorXd& { return s.z; });
  c.push_back({"energy", K::kReal, [](const Sample& s) -> Cell { return s.energy; }});
  return c;
}

Columns<ContactEvent> ImpactColumns(int dofs) {
  Columns<ContactEvent> c{{"t", K::kReal, [](const ContactEvent& e) -> Cell { return e.t; }},
                          {"contact", K::kInteger, [](const ContactEvent& e) -> Cell { return long{e.contact + 1}; }}};
  AddState<ContactEvent>(c, dofs, "_before", [](const ContactEvent& e) -> const Eigen::VectorXd& { return e.before; });
  AddState<ContactEvent>(c, dofs, "_after", [](const ContactEvent& e) -> const Eigen::VectorXd& { return e.after; });
  return c;
}

}  // namespace nsmodal::report
