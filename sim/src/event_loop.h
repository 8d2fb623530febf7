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
//   void Impact(int j, double e);    Newton's law on contact j
//   void Hold(int j);                v_c -> 0 and the held motion from here
//   void Release(int j);             free flight from the held state
//   void Restart();                  after every contact decision
//   void Finish(SimulationSummary&); steps, final time and state
// and is built from (cm, x0, v0, options). Each integrator's file defines its
// Stepper and instantiates RunIntegrator with it (integrators.h declares them).
#include <Eigen/Dense>
#include <optional>
#include <stdexcept>
#include <string>

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
    kWitness,   // contact `contact`'s witness fired: a contact if open, a release if held
    kCaptured,  // an event-capturing step resolved an impact itself (`event`)
    kFailed,    // the integrator cannot go on (`message`)
  };
  Event event = Event::kNone;
  int contact = 0;
  double held = 0.0;  // the time of this advance spent held (sticking)
  ContactEvent event_states;  // kCaptured: the states before and after
  std::string message;
};

struct ContactKinematics {
  double velocity = 0.0;      // into the wall (> 0 moving in)
  double acceleration = 0.0;  // free, into the wall (> 0 pushed in)
  ContactResolution resolution;
};

template <typename Stepper>
SimulationSummary RunEventLoop(Stepper& s, const ContactModel& cm, const SimulateOptions& opt,
                               const SimulationObserver& observer) {
  const double e = cm.model.restitution;
  SimulationSummary sum;
  bool held = false;
  Sampler sampler(opt, observer);
  sampler.Emit(0.0, [&](double) { return s.Physical(); });

  // contact.h's decision at contact j, with the integrator's resolution.
  auto handle_contact = [&](int j) {
    const ContactKinematics k = s.Contact(j);
    const ContactDecision dec = DecideContact(k.velocity, k.acceleration, e, k.resolution);
    if (dec.outcome == ContactOutcome::kGraze) {
      ++sum.grazes;
    } else if (dec.outcome != ContactOutcome::kHold) {
      ContactEvent ev;
      if (observer.on_impact) ev = ContactEvent{s.Time(), s.Physical(), {}};
      s.Impact(j, e);
      ++sum.impacts;
      if (observer.on_impact) {
        ev.after = s.Physical();
        observer.on_impact(ev);
      }
    }
    if (dec.outcome == ContactOutcome::kImpactZeno) {
      ++sum.zeno_events;
      if (sum.first_zeno_time < 0.0) sum.first_zeno_time = s.Time() + dec.accumulation;
      sum.sticking_time -= dec.accumulation;  // held from the accumulation time on
    }
    if (dec.outcome != ContactOutcome::kGraze && dec.outcome != ContactOutcome::kImpact) {
      s.Hold(j);
      held = true;
      ++sum.sticking_phases;
    }
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
          ++sum.impacts;
          if (observer.on_impact) observer.on_impact(a.event_states);
          break;
        case Advance::Event::kWitness:
          if (held) {
            s.Release(a.contact);
            held = false;
            s.Restart();
          } else {
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
