#include "nsmodal/family_parameter.h"

#include <algorithm>
#include <cmath>

#include "nsmodal/error.h"
#include "nsmodal/response.h"
#include "nsmodal/stop.h"

namespace nsmodal {

namespace {

using Kind = ModelParameter::Kind;

std::vector<Transition> Transitions(const Model& model, const PeriodGrid& periods, const std::string& period_field) {
  const AnalysisBasis b(ConservativeTwin(model));
  CheckSweepWork(b, periods, {1}, period_field, true);
  return SweepTransitions(b, ComputeSweep(b, periods, 1));
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
  std::vector<Transition> own;
  double d0 = 0.0;
  if (out.scaled) {
    own = Transitions(model, periods, period_field);
    d0 = model.contacts.front().gap;
    out.notes.push_back("the gap only scales the family (x by d / d0, energy by (d / d0)^2, T unchanged): swept "
                        "once at " + p.name + " = " + FormatValue(d0) + " and rescaled");
  }
  std::vector<FamilyRow> previous;
  const double near = 3.0 * periods.step;
  for (std::size_t k = 0; k < v.size(); ++k) {
    ThrowIfStopRequested();
    if (progress) progress(static_cast<long>(k), static_cast<long>(v.size()));
    std::vector<Transition> here = own;
    if (out.scaled) {
      const double s = v[k] / d0;
      for (Transition& t : here) t.energy *= s * s;
    } else {
      here = Transitions(models[k], periods, period_field);
    }
    std::vector<FamilyRow> current;
    std::vector<bool> taken(previous.size(), false);
    for (const Transition& t : here) {
      // The track of the nearest unlinked point of the same kind and contact
      // at the previous value.
      int best = -1;
      for (std::size_t j = 0; j < previous.size(); ++j) {
        const Transition& q = previous[j].transition;
        if (taken[j] || q.kind != t.kind || q.contact != t.contact) continue;
        const double dt = std::abs(q.period - t.period);
        if (dt > std::max(near, 0.05 * t.period)) continue;
        if (best < 0 || dt < std::abs(previous[static_cast<std::size_t>(best)].transition.period - t.period)) {
          best = static_cast<int>(j);
        }
      }
      int track = out.tracks;
      if (best >= 0) {
        taken[static_cast<std::size_t>(best)] = true;
        track = previous[static_cast<std::size_t>(best)].track;
      } else {
        ++out.tracks;
      }
      current.push_back({v[k], t, track});
    }
    out.rows.insert(out.rows.end(), current.begin(), current.end());
    previous = std::move(current);
  }
  if (progress) progress(static_cast<long>(v.size()), static_cast<long>(v.size()));
  return out;
}

}  // namespace nsmodal
