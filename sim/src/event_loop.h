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
//   Eigen::VectorXd Physical() const;        the state (x, v) now
//   void Impact(int j, double e);    Newton's law on contact j (and on every
//                                    other contact struck at the same instant)
//   void Hold(int j);                n_j . v -> 0 and the held motion from here
//   void Release(int j);             free flight from the held state
//   void Restart();                  after every contact decision
//   void Finish(SimulationSummary&); steps, final time and state
// and is built from (cm, x0, v0, options). Each integrator's file defines its
// Stepper and instantiates RunIntegrator with it (integrators.h declares them).
#include <Eigen/Dense>
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
    kWitness,   // contact `contact`'s witness fired: its release if it is the
                // held one, else a contact (the held one, if any, is released first)
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

// Consecutive holds, each starting within this many zeno_flight of the
// previous one's end on another contact, that mean several contacts are
// held at once: a state the integrators' sticking flows (one held contact)
// do not model; the run ends with a solver error saying so instead of
// alternating between them for ever.
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
  int held = -1;  // the held contact (-1: none)
  int alternating = 0;
  double released_at = -1.0;
  int released = -1;
  const double zeno_span = opt.zeno_flight * 2.0 * M_PI / cm.basis.omega.maxCoeff();
  Sampler sampler(opt, observer);
  sampler.Emit(0.0, [&](double) { return s.Physical(); });

  auto count_impact = [&](int j) {
    ++sum.impacts;
    ++sum.impacts_per_contact[j];
  };
  // contact.h's decision at contact j, with the integrator's resolution.
  auto handle_contact = [&](int j) {
    const double e = cm.contact(j).restitution;
    const ContactKinematics kin = s.Contact(j);
    const ContactDecision dec = DecideContact(kin.velocity, kin.acceleration, e, kin.resolution);
    if (dec.outcome == ContactOutcome::kGraze) {
      ++sum.grazes;
      ++sum.grazes_per_contact[j];
    } else if (dec.outcome != ContactOutcome::kHold) {
      ContactEvent ev;
      if (observer.on_impact) ev = ContactEvent{s.Time(), s.Physical(), {}, j};
      s.Impact(j, e);
      count_impact(j);
      if (observer.on_impact) {
        ev.after = s.Physical();
        observer.on_impact(ev);
      }
    }
    if (dec.outcome == ContactOutcome::kImpactZeno) {
      ++sum.zeno_events;
      ++sum.zeno_per_contact[j];
      if (sum.first_zeno_time < 0.0) sum.first_zeno_time = s.Time() + dec.accumulation;
      sum.sticking_time -= dec.accumulation;  // held from the accumulation time on
    }
    if (dec.outcome != ContactOutcome::kGraze && dec.outcome != ContactOutcome::kImpact) {
      if (released >= 0 && released != j && s.Time() - released_at <= zeno_span) {
        if (++alternating >= kMaxAlternatingHolds) {
          throw SolverError("contacts " + std::to_string(released + 1) + " and " + std::to_string(j + 1) +
                            " are held at once at t = " + std::to_string(s.Time()) +
                            ": several contacts held together are not modelled by this integrator yet");
        }
      } else {
        alternating = 0;
      }
      s.Hold(j);
      held = j;
      ++sum.sticking_phases;
      ++sum.sticking_per_contact[j];
    }
    s.Restart();
  };
  auto release = [&]() {
    s.Release(held);
    released = held;
    released_at = s.Time();
    held = -1;
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
          for (int j : a.captured) count_impact(j);
          if (observer.on_impact) observer.on_impact(a.event_states);
          break;
        case Advance::Event::kWitness:
          if (held == a.contact) {
            release();
            s.Restart();
          } else {
            if (held >= 0) release();  // another contact struck while held: free first
            handle_contact(a.contact);
          }
          break;
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
