#include "nsmodal/family_parameter.h"

#include <algorithm>
#include <cmath>

#include "nsmodal/bridge.h"
#include "nsmodal/error.h"
#include "nsmodal/response.h"
#include "nsmodal/stop.h"

namespace nsmodal {

namespace {

using Kind = ModelParameter::Kind;

// The family's special points at one model, by period.
std::vector<FamilyRow> Points(const Model& model, const PeriodGrid& periods, const std::string& period_field) {
  const AnalysisBasis b(ConservativeTwin(model));
  CheckSweepWork(b, periods, {1}, period_field, true);
  std::vector<FamilyRow> out;
  for (const Transition& t : SweepTransitions(b, ComputeSweep(b, periods, 1))) {
    out.push_back({0.0, t.period, ToString(t.kind), t.energy, t.contact, 0});
    // Bridges are contact 1's own (bridge.h), at its grazings and period doublings.
    if (model.contacts.size() != 1) continue;
    BridgeSearch found;
    if (t.kind == TransitionKind::kGrazing) {
      found = FindBridgeAt(b, t.period);
    } else if (t.kind == TransitionKind::kMultiplierMinusOne) {
      found = FindPeriodDoublingBridge(b, t.period);
    } else {
      continue;
    }
    if (found.found()) out.push_back({0.0, found.bridge.period, "bridge", found.bridge.energy_min, 0, 0});
  }
  std::stable_sort(out.begin(), out.end(), [](const FamilyRow& a, const FamilyRow& b) { return a.period < b.period; });
  return out;
}

}  // namespace

void CheckFamilyRequest(const Model& model, const ModelParameter& p, const PeriodGrid& values,
                        const PeriodGrid& periods, const std::string& field, const std::string& range,
                        const std::string& period_field) {
  if (p.kind != Kind::kMass && p.kind != Kind::kSpring && p.kind != Kind::kGap) {
    throw InputError(field, "'" + p.name + "' does not change the free (e = 1) family, the conservative twin's: "
                            "follow a mass, a spring or a gap (or give the scene a [forcing] table to follow its "
                            "forced response)");
  }
  values.Validate(range);
  periods.Validate(period_field);
  // (The model's checks are intervals in each parameter: both ends suffice.)
  for (const double x : {values.from, values.to}) WithParameter(model, p, x);
  CheckSweepWork(AnalysisBasis(ConservativeTwin(model)), periods, {1}, period_field, true);
}

FamilyContinuation FollowFamily(const Model& model, const ModelParameter& p, const PeriodGrid& values,
                                const PeriodGrid& periods, const std::function<void(long, long)>& progress,
                                const std::string& field, const std::string& range, const std::string& period_field) {
  CheckFamilyRequest(model, p, values, periods, field, range, period_field);
  std::vector<double> v = values.Values();
  for (double& x : v) x = std::min(x, values.to);
  std::vector<Model> models;
  for (const double x : v) models.push_back(WithParameter(model, p, x));
  FamilyContinuation out;
  out.scaled = p.kind == Kind::kGap && model.contacts.size() == 1;
  std::vector<FamilyRow> own;
  double d0 = 0.0;
  if (out.scaled) {
    own = Points(model, periods, period_field);
    d0 = model.contacts.front().gap;
    out.notes.push_back("the gap only scales the family (x by d / d0, energy by (d / d0)^2, T unchanged): swept "
                        "once at " + p.name + " = " + FormatValue(d0) + " and rescaled");
  }
  std::vector<FamilyRow> previous;
  const double near = 3.0 * periods.step;
  for (std::size_t k = 0; k < v.size(); ++k) {
    ThrowIfStopRequested();
    if (progress) progress(static_cast<long>(k), static_cast<long>(v.size()));
    std::vector<FamilyRow> here = own;
    if (out.scaled) {
      const double s = v[k] / d0;
      for (FamilyRow& r : here) r.energy *= s * s;
    } else {
      here = Points(models[k], periods, period_field);
    }
    std::vector<bool> taken(previous.size(), false);
    for (FamilyRow& r : here) {
      r.parameter = v[k];
      // The track of the nearest unlinked point of the same kind and contact
      // at the previous value.
      int best = -1;
      for (std::size_t j = 0; j < previous.size(); ++j) {
        const FamilyRow& q = previous[j];
        if (taken[j] || q.kind != r.kind || q.contact != r.contact) continue;
        const double dt = std::abs(q.period - r.period);
        if (dt > std::max(near, 0.05 * r.period)) continue;
        if (best < 0 || dt < std::abs(previous[static_cast<std::size_t>(best)].period - r.period)) {
          best = static_cast<int>(j);
        }
      }
      if (best >= 0) {
        taken[static_cast<std::size_t>(best)] = true;
        r.track = previous[static_cast<std::size_t>(best)].track;
      } else {
        r.track = out.tracks++;
      }
    }
    out.rows.insert(out.rows.end(), here.begin(), here.end());
    previous = std::move(here);
  }
  if (progress) progress(static_cast<long>(v.size()), static_cast<long>(v.size()));
  return out;
}

}  // namespace nsmodal
