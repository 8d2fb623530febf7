#pragma once
// Witnesses: the scalar functions of the state whose crossings are the events
// of a simulation (after Drake's witness functions,
// systems/framework/witness_function.h). Each contact has one witness at a
// time:
//   open   its gap, w = d - x_c (positive while the mass is clear of the wall);
//   held   its contact force, w = lambda (positive while the wall pushes the
//          held mass back; lambda = a_c / (M^-1)_cc, a_c the free contact
//          acceleration).
//
// Trigger rule (direction kPositiveThenNonPositive). Over a step that starts
// at t0 and ends at t1, the witness fires on the half-open interval (t0, t1]
// if and only if
//        w(t0) > 0   and   w(t1) <= 0,
// measured against the integrator's resolution band (w taken as the gap less
// the band's half-width: the exact integrator's root_tol band, CVODE's
// xtol; simulate.h). The event is placed at the first crossing the integrator
// locates inside the step. Consequences the event loop relies on:
//   - a witness exactly zero at t0 does not fire on that step: the gap right
//     after an impact (the search is not armed until the gap has opened by
//     2 bands, first_rise.h; CVODE keeps a root function that is zero at a
//     restart inactive until it moves away) and the force right after a hold;
//   - a sign change inside the step fires, however short the excursion (the
//     exact search cannot step over it; CVODE's step is checked for a
//     crossing it did not report, cvode.cc);
//   - a tangency (w touches 0 from above with no sign change: a graze) is not
//     a crossing: each integrator finds it through the gap's derivative (the
//     exact search stops in the band; CVODE's companion root on v_c) and hands
//     it to the graze logic (contact.h, DecideContact), which counts a graze
//     and applies no impulse.
#include <string>

namespace nsmodal {

enum class WitnessDirection { kPositiveThenNonPositive };

enum class WitnessKind {
  kGap,           // the contact is open: an impact (or a graze) when it fires
  kContactForce,  // the contact is held: the mass is released when it fires
};

struct Witness {
  std::string name;  // "contact 1 gap", "contact 1 force"
  WitnessKind kind = WitnessKind::kGap;
  int contact = 0;   // 0-based index of the contact
  WitnessDirection direction = WitnessDirection::kPositiveThenNonPositive;
};

// The contact's witness in its state (open or held).
Witness ContactWitness(int contact, bool held);

// The rule above for the values at a step's ends.
constexpr bool Fires(WitnessDirection direction, double w0, double w1) {
  switch (direction) {
    case WitnessDirection::kPositiveThenNonPositive: return w0 > 0.0 && w1 <= 0.0;
  }
  return false;
}

}  // namespace nsmodal
