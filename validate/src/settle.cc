#include "nsmodal/settle.h"

#include <algorithm>
#include <cmath>

#include "nsmodal/error.h"
#include "nsmodal/simulate.h"

namespace nsmodal {

void SettleOptions::Validate() const {
  if (window < 2 || window > 1024) {
    throw InputError("window", "must be between 2 and 1024 stroboscopic samples, got " + std::to_string(window));
  }
  if (periods <= window || periods > 100000000) {
    throw InputError("periods", "must exceed the window (" + std::to_string(window) + ") and be at most 1e8, got " +
                                    std::to_string(periods));
  }
  if (!(tol > 0.0) || !(tol < 1.0)) throw InputError("tol", "must be in (0, 1), got " + FormatValue(tol));
  if (!(phase >= 0.0 && phase < 2.0 * M_PI)) {
    throw InputError("phase", "must be in [0, 2 pi), got " + FormatValue(phase));
  }
}

Settled Settle(const Model& model, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0, const SettleOptions& o) {
  o.Validate();
  if (!model.forcing.HasHarmonic()) {
    throw InputError("forcing.amplitude", "is needed: a basin classifies motions by their stroboscopic period");
  }
  const double tf = 2.0 * M_PI / model.forcing.frequency;
  SimulateOptions s;
  s.t_end = o.periods * tf;
  s.t_start = o.phase / model.forcing.frequency;
  s.sample_dt = 0.0;
  for (int k = 0; k <= o.window; ++k) s.sample_times.push_back(std::min(s.t_end, (o.periods - o.window + k) * tf));
  std::vector<Eigen::VectorXd> z;
  struct Hit {
    double t;
    int contact;
    double velocity;  // into the wall, before
  };
  std::vector<Hit> hits;  // the impacts of the window
  const double window_start = (o.periods - o.window) * tf;
  SimulationObserver obs;
  obs.on_sample = [&z](double, const Eigen::VectorXd& state) { z.push_back(state); };
  obs.on_impact = [&](const ContactEvent& e) {
    if (e.t > window_start) {
      hits.push_back({e.t, e.contact,
                      model.contacts[static_cast<std::size_t>(e.contact)].Along(e.before.tail(model.dofs()))});
    }
  };
  const SimulationSummary sum = Simulate(model, x0, v0, s, obs);
  Settled out;
  out.zeno_or_sticking = sum.zeno_events > 0 || sum.sticking_phases > 0;
  if (sum.status != SimulationStatus::kFinished || static_cast<int>(z.size()) != o.window + 1) {
    out.message = "the simulation ended early: " + ToString(sum.status) + (sum.message.empty() ? "" : ": " + sum.message);
    return out;
  }
  double scale = 0.0;
  for (const Eigen::VectorXd& q : z) scale = std::max(scale, q.cwiseAbs().maxCoeff());
  for (const Contact& c : model.contacts) scale = std::max(scale, c.gap);
  const int last = o.window;
  for (int n = 1; n <= o.window / 2; ++n) {
    double worst = 0.0;
    for (int k = last - n; k <= last; ++k) worst = std::max(worst, (z[k] - z[k - n]).cwiseAbs().maxCoeff() / scale);
    out.repetition = worst;
    if (worst > o.tol) continue;
    out.settled = true;
    out.period = n;
    int best = last - n + 1;
    for (int k = last - n + 1; k <= last; ++k) {
      if (z[k][0] < z[best][0]) best = k;
    }
    out.state = z[best];
    const double t0 = (o.periods - o.window + best) * tf;
    // The impacts of one period of the attractor, from the canonical sample:
    // those of the last n periods, shifted into [t0, t0 + n T_f), in order.
    std::vector<Hit> period;
    for (Hit h : hits) {
      if (h.t <= s.t_end - n * tf) continue;
      h.t -= t0;
      if (h.t < 0.0) h.t += n * tf;
      period.push_back(h);
    }
    std::sort(period.begin(), period.end(), [](const Hit& a, const Hit& b) { return a.t < b.t; });
    for (const Hit& h : period) {
      out.impact_times.push_back(h.t);
      out.impact_contacts.push_back(h.contact);
      out.impact_velocities.push_back(h.velocity);
    }
    return out;
  }
  out.message = "no period up to " + std::to_string(o.window / 2) + " forcing periods repeats to " + FormatValue(o.tol) +
                " after " + std::to_string(o.periods) + " periods";
  return out;
}

}  // namespace nsmodal
