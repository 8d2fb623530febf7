#pragma once
// The one event loop of the three integrators (simulate.h). Internal.
//
// The loop owns what is the same for every integrator: the stop requests
// (a signal, stop.h; the observer's), the step limit, progress, the sampler,
// the contact decision of contact.h (graze, impact, hold, Zeno) and its
// counts, the impact events, the sticking phases and their time, and the
// release. An integrator (a Stepper) only advances: free or held, to the
// next witness crossing (witness.h's rule) or output time, emitting the
// samples of the stretch it advanced through the loop's sampler (the times
// are the loop's, the interpolant the integrator's), and applies what the
// loop decides (an impulse, a hold, a release).
//
// A Stepper provides:
//   bool Finished() const;           the end time reached
//   double Time() const;
//   long Steps() const;              what opt.max_steps counts
//   std::optional<int> InitialContact();  the start is a contact (of that index)
//   Advance Step(Sampler&);          advance once (see Advance)
//   ContactKinematics Contact(int j) const;  at the contact just found
//   ContactKinematics Resting(int j);        contact j now (on its wall), free or held
//   Eigen::VectorXd Physical() const;        the state (x, v) now
//   const std::vector<int>& Impact(int j, double e);  Newton's law on contact j (and on
//                                    every other contact struck at the same
//                                    instant); returns the contacts given an impulse
//   void Hold(int j);                n_j . v -> 0 and the held motion from here
//   void Release(int j);             free flight from the held state
//   void Restart();                  after every contact decision
//   void Finish(SimulationSummary&); steps, final time and state
// and is built from (cm, x0, v0, options). Each integrator's file defines its
// Stepper and instantiates RunIntegrator with it (integrators.h declares them).
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "integrators.h"
#include "nsmodal/contact.h"
#include "nsmodal/stop.h"

namespace nsmodal::internal {

// A solver's own failure (CVODE's flags): the run ends with kSolverError.
class SolverError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Advance {
  enum class Event {
    kNone,      // reached an output time, a step's end or the end
    kWitness,   // contact `contact`'s witness fired: its release if it is held,
                // else a contact (decided on the held motion if others are held)
    kCaptured,  // an event-capturing step resolved impacts itself (`event_states`, at `captured`)
    kFailed,    // the integrator cannot go on (`message`)
  };
  Event event = Event::kNone;
  int contact = 0;
  std::vector<int> captured;  // kCaptured: the contacts struck in the step
  double held = 0.0;  // the time of this advance spent held (sticking)
  ContactEvent event_states;  // kCaptured: the states before and after
  std::string message;
};

struct ContactKinematics {
  double velocity = 0.0;      // into the wall (> 0 moving in)
  double acceleration = 0.0;  // free, into the wall (> 0 pushed in)
  ContactResolution resolution;
};

// Consecutive holds, each starting within zeno_flight of the previous
// release of another contact: contacts that take turns being held without
// time passing. Several contacts held at once are modelled (a held set); this
// bounds what would otherwise loop for ever (a set the held flows cannot
// represent): the run ends with a solver error saying so.
inline constexpr int kMaxAlternatingHolds = 8;

template <typename Stepper>
SimulationSummary RunEventLoop(Stepper& s, const ContactModel& cm, const SimulateOptions& opt,
                               const SimulationObserver& observer) {
  const int k = cm.NumContacts();
  SimulationSummary sum;
  sum.impacts_per_contact.assign(k, 0);
  sum.grazes_per_contact.assign(k, 0);
  sum.zeno_per_contact.assign(k, 0);
  sum.sticking_per_contact.assign(k, 0);
  std::vector<int> held;  // the held contacts
  int alternating = 0;
  double released_at = -1.0;
  int released = -1;
  const double zeno_span = ZenoFlightTime(cm, opt);
  Sampler sampler(opt, observer);
  sampler.Emit(s.Time(), [&](double) { return s.Physical(); });

  auto hold = [&](int j, bool counted = true) {
    if (!counted) {
      // A contact that stays on its wall through an impact elsewhere.
    } else if (released >= 0 && released != j && s.Time() - released_at <= zeno_span) {
      if (++alternating >= kMaxAlternatingHolds) {
        throw SolverError("contacts " + std::to_string(released + 1) + " and " + std::to_string(j + 1) +
                          " take turns being held at t = " + std::to_string(s.Time()) +
                          " without time passing: not resolved by this integrator");
      }
    } else {
      alternating = 0;
    }
    s.Hold(j);
    held.push_back(j);
    if (counted) {  // (a contact held on through an impact elsewhere never left its wall: the same phase)
      ++sum.sticking_phases;
      ++sum.sticking_per_contact[j];
    }
  };
  auto release = [&](int j) {
    s.Release(j);
    held.erase(std::find(held.begin(), held.end(), j));
    released = j;
    released_at = s.Time();
  };
  auto count_impact = [&](int j) {
    ++sum.impacts;
    ++sum.impacts_per_contact[j];
  };
  auto count_graze = [&](int j) {
    ++sum.grazes;
    ++sum.grazes_per_contact[j];
  };
  // contact.h's decision at contact j, with the integrator's resolution.
  // others_held: contacts were held just before (released for this impact;
  // they stay held through it if it leaves them at rest): the time to a Zeno
  // accumulation is then held time already.
  auto handle_contact = [&](int j, bool others_held = false) {
    const double e = cm.contact(j).restitution;
    const ContactKinematics kin = s.Contact(j);
    const ContactDecision dec = DecideContact(kin.velocity, kin.acceleration, e, kin.resolution);
    if (dec.outcome == ContactOutcome::kGraze) {
      count_graze(j);
    } else if (dec.outcome != ContactOutcome::kHold) {
      ContactEvent ev;
      if (observer.on_impact) ev = ContactEvent{s.Time(), s.Physical(), {}, j};
      // Every contact the impulse acts on is an impact (several struck at
      // once: one event each, with the same states).
      const std::vector<int>& struck = s.Impact(j, e);
      for (int c : struck) count_impact(c);
      if (observer.on_impact) {
        ev.after = s.Physical();
        for (int c : struck) {
          ev.contact = c;
          observer.on_impact(ev);
        }
      }
    }
    if (dec.outcome == ContactOutcome::kImpactZeno) {
      ++sum.zeno_events;
      ++sum.zeno_per_contact[j];
      if (sum.first_zeno_time < 0.0) sum.first_zeno_time = s.Time() + dec.accumulation;
      if (!others_held) sum.sticking_time -= dec.accumulation;  // held from the accumulation time on
    }
    if (dec.outcome != ContactOutcome::kGraze && dec.outcome != ContactOutcome::kImpact) hold(j);
    s.Restart();
  };

  long next_progress = 0;
  try {
    if (const std::optional<int> j = s.InitialContact()) handle_contact(*j);
    while (!s.Finished()) {
      ThrowIfStopRequested();  // a signal (stop.h): the run unwinds
      if (observer.stop_requested && observer.stop_requested()) {
        sum.status = SimulationStatus::kStopped;
        break;
      }
      if (s.Steps() >= opt.max_steps) {
        sum.status = SimulationStatus::kStepLimit;
        sum.message = "step limit reached at t = " + std::to_string(s.Time());
        break;
      }
      if (observer.on_progress && s.Steps() >= next_progress) {
        observer.on_progress(s.Time());
        next_progress = s.Steps() + 100000;
      }
      const Advance a = s.Step(sampler);
      sum.sticking_time += a.held;
      switch (a.event) {
        case Advance::Event::kNone: break;
        case Advance::Event::kFailed:
          sum.status = SimulationStatus::kSolverError;
          sum.message = a.message;
          break;
        case Advance::Event::kCaptured:
          for (int j : a.captured) {
            count_impact(j);
            if (observer.on_impact) {
              ContactEvent ev = a.event_states;
              ev.contact = j;
              observer.on_impact(ev);
            }
          }
          break;
        case Advance::Event::kWitness: {
          const int j = a.contact;
          if (std::find(held.begin(), held.end(), j) != held.end()) {
            release(j);
            s.Restart();
          } else if (!held.empty()) {
            // Another contact reached while some are held: decided on the
            // held motion. At rest and pushed in, it joins them; a graze
            // leaves them; an impact frees them all first.
            const ContactKinematics kin = s.Contact(j);
            const ContactDecision dec =
                DecideContact(kin.velocity, kin.acceleration, cm.contact(j).restitution, kin.resolution);
            if (dec.outcome == ContactOutcome::kGraze) {
              count_graze(j);
              s.Restart();
            } else if (dec.outcome == ContactOutcome::kHold) {
              hold(j);
              s.Restart();
            } else {
              // An impact: Newton's law over it and the held contacts (in
              // their bands, at rest: struck at once, contact.h); of those
              // the impulse leaves at rest, the ones the forces of Moreau's
              // acceleration-level law keep (with those held now) stay held
              // (contact.h HeldByForces).
              const std::vector<int> was = held;
              while (!held.empty()) release(held.back());
              handle_contact(j, true);
              std::vector<int> rest;
              for (int h : was) {
                if (std::find(held.begin(), held.end(), h) != held.end()) continue;
                const ContactKinematics kin_h = s.Resting(h);
                if (std::abs(kin_h.velocity) <= kin_h.resolution.vtol) rest.push_back(h);
              }
              if (!rest.empty()) {
                std::vector<int> set = held;
                set.insert(set.end(), rest.begin(), rest.end());
                std::vector<int> keep;
                if (!cm.HeldByForces(set, s.Time(), s.Physical(), keep)) {
                  throw SolverError("the LCP of the forces of the contacts at rest at t = " +
                                    std::to_string(s.Time()) + " has no solution");
                }
                for (int h : rest) {
                  if (std::find(keep.begin(), keep.end(), h) == keep.end()) continue;
                  hold(h, false);
                  s.Restart();
                }
              }
            }
          } else {
            handle_contact(j);
          }
          break;
        }
      }
      if (sum.status == SimulationStatus::kSolverError) break;
    }
  } catch (const SolverError& ex) {
    sum.status = SimulationStatus::kSolverError;
    sum.message = ex.what();
  }
  s.Finish(sum);
  return sum;
}

template <typename Stepper>
SimulationSummary RunIntegrator(const ContactModel& cm, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0,
                                const SimulateOptions& opt, const SimulationObserver& observer) {
  Stepper stepper(cm, x0, v0, opt);
  return RunEventLoop(stepper, cm, opt, observer);
}

}  // namespace nsmodal::internal
