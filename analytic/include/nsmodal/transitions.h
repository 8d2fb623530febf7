#pragma once
// Transitions of the admissible zones of the 1-ipp family (paper section 2.1):
//   singular  - D(T) = 0 (eq. 23): the energy goes to infinity;
//   modal     - T = k T_i (eq. 24): the orbit becomes a linear mode grazing d;
//   grazing   - an interior maximum of x_c reaches d (the bridge to m > 1).
// Each is located by refinement, not by the grid step: singular periods are the
// roots of D between consecutive poles k T_i (D decreases strictly there, so
// there is exactly one), modal periods are exact, and grazing periods are the
// roots of h(T) = max over interior maxima of x_c - d, polished by Brent.
#include <string>
#include <vector>

#include "nsmodal/modal_basis.h"

namespace nsmodal {

// kSingular, kModal, kGrazing bound the admissible zones (paper section
// 2.1); kMultiplierPlusOne / kMultiplierMinusOne are stability changes inside
// a zone: a nontrivial pair of Floquet multipliers through +1 (an extremum of
// E(T)) or -1 (a period doubling), issue 13.
enum class TransitionKind { kSingular, kModal, kGrazing, kMultiplierPlusOne, kMultiplierMinusOne };
std::string ToString(TransitionKind kind);
// True for kSingular, kModal, kGrazing: the ends of the admissible zones.
inline bool BoundsAZone(TransitionKind kind) {
  return kind == TransitionKind::kSingular || kind == TransitionKind::kModal || kind == TransitionKind::kGrazing;
}

struct Transition {
  double period = 0.0;
  TransitionKind kind = TransitionKind::kGrazing;
  double energy = 0.0;  // infinite for a singular transition
  // The contact concerned (0-based): the family's own, or for kGrazing the
  // contact whose gap closes (another contact's: where this family meets
  // those that strike it too, issue 24).
  int contact = 0;
};

// The stability changes of the admissible 1-ipp family on a grid of periods
// (each cell with both ends admissible): sign changes in T of Gt(2; T) (+1)
// and Gt(-2; T) (-1) of stability.h, O(N) each, polished by Brent to ~1e-15
// relative; a sign change through a pole of Gt (|Gt| at the polished point
// not below 1e-6 of its values at the cell's ends) is not a crossing. Sorted,
// energies of the orbit there.
//
// Each function takes the family's contact (0-based, the sequence (j); default
// contact 1).
std::vector<Transition> OneImpactMultiplierCrossings(const AnalysisBasis& b, const std::vector<double>& periods,
                                                     const std::vector<bool>& admissible, int contact = 0);
// Both lists (OneImpactTransitions, then the crossings) in one, sorted by T:
// the rows of transitions.csv.
std::vector<Transition> OneImpactTransitionsAndCrossings(const AnalysisBasis& b, const std::vector<double>& periods,
                                                         const std::vector<bool>& admissible, int contact = 0);

// Every root of D(T) in [from, to].
std::vector<double> SingularPeriods(const AnalysisBasis& b, double from, double to, int contact = 0);
// Every k T_i in [from, to] (modes that do not move x_c, r_i = 0, excluded).
std::vector<double> ModalPeriods(const AnalysisBasis& b, double from, double to, int contact = 0);

// h(T): the largest x_c - d at an interior maximum of the 1-ipp orbit of period T.
double GrazingFunction(const AnalysisBasis& b, double period, int contact = 0);
// g(T): the largest n_k . x - d_k of the other contacts over the 1-ipp orbit
// of period T on `contact` (Orbit::other_excess; -inf with one contact).
double OtherGrazingFunction(const AnalysisBasis& b, double period, int contact);

// The boundaries of the admissible 1-ipp zones seen on an increasing grid of
// periods whose admissibility is already known (admissible[j] for periods[j]),
// each refined and classified. Two boundaries inside one grid cell cancel and
// are not seen; anything else is.
// An admissibility change with no own-contact grazing in its cell is
// looked for as another contact's grazing (OtherGrazingFunction).
std::vector<Transition> OneImpactTransitions(const AnalysisBasis& b, const std::vector<double>& periods,
                                             const std::vector<bool>& admissible, int contact = 0);
// The same on the grid from:to:step, evaluating admissibility itself.
std::vector<Transition> OneImpactTransitions(const AnalysisBasis& b, double from, double to, double step);

}  // namespace nsmodal
