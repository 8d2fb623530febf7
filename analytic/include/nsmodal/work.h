#pragma once
// Estimates of an analysis' work, made before it starts (issue 29): every
// analysis accepted within the documented limits finishes, and one beyond them
// is refused at once with its estimate and how to lower it.
//
// The work of the periodic-orbit analysis grows with the number of
// oscillations of the fastest mode in a period: every search of a flight of
// duration tau isolates the roots of a sum of sinusoids of frequencies up to
// w_max (roots.h IsolateRoots), about w_max tau / pi of them
// (HalfOscillations), and each root costs a few dozen evaluations of a sum of
// N terms (the modes kept).
//   m = 1, at period T: the NC3 search of its one flight: H(T) roots;
//   m = 2: the roots of P(t2) (two_impact.h), up to H(T), each a potential
//          orbit whose NC3 search scans its two flights, of total duration T:
//          H(T) (1 + H(T)) roots: quadratic in w_max T.
// Summed over a grid of periods, times (N + kRootOverhead), this is
// SweepWork: "mode-root evaluations". (Not counted: the stability of each
// orbit, O(N^2) for m = 1 and O(N^3) for m = 2, which does not grow with T.
// Validation's simulations have their own estimate: validate.h,
// CheckValidationWork.)
#include <string>
#include <vector>

#include "nsmodal/modal_basis.h"

namespace nsmodal {

// H(tau) = w_max tau / pi + 2: the half-oscillations of the fastest mode in a
// duration tau, an estimate (from above, up to the +2) of the roots a search
// of a sum of sinusoids isolates on it.
double HalfOscillations(const ModalBasis& b, double duration);

// The cost of one root, in evaluations of one mode's term: about 40 halvings
// and a Brent polish, each a sum of N terms plus a fixed overhead worth about
// kRootOverhead terms. Measured (Release, one core): the paper's system,
// N = 2, 1.6 us a root (2-ipp at T = 2,000: 1.8e6 roots, 2.9 s); a chain of
// 1,000 unit masses, 140 us a root: both ~0.15 us per unit of N + 8.
inline constexpr double kRootOverhead = 8.0;

// The work of the m-ipp sweep (m = 1 or 2) over the periods
// from, from + step, ..., count of them: sum over T of roots(T) (N + kRootOverhead).
double SweepWork(const AnalysisBasis& b, double from, double step, long count, int impacts);

// The work of the transitions search of the 1-ipp family over [from, to]
// (transitions.h): every modal period k T_i and singular period in the range
// is probed by an evaluated orbit on each side, and the grazing searches
// between them cost about as much again: 4 S H(to) (N + kRootOverhead) with S
// the number of modal periods, counted twice (the singular ones sit between
// them). Many modes or a large w_max T crowd them: a 100-element bar over
// 0.1:0.77 ms has S ~ 5,000.
double TransitionsWork(const AnalysisBasis& b, double from, double to);

// The most work (SweepWork + TransitionsWork) accepted in one analysis, over
// all its sweeps: at ~0.15 us a unit, about 30 s on one core. Measured on the
// paper's system: 2-ipp at T = 4,000 (7.2e7, P with its full 2,689 roots)
// 15 s; at T = 6,500 (1.9e8, 1,277 roots found of the 4,359 estimated)
// 8.7 s. Set so that the documented runs still run (the quick start's and
// `figures`' sweeps: below 2e7; bench_analytic's 1-ipp sweep of a 1,000-mass
// chain over 0.5:60:0.01: 1.3e8) and T = 10,000 (4.5e8) is refused.
inline constexpr double kMaxSweepWork = 2e8;

// Throws InputError naming `field` when the sweeps of `impacts` (1 and/or 2)
// over the grid exceed kMaxSweepWork, with the estimate (the fastest mode's
// oscillations per period, the roots to isolate, the modes kept) and how to
// lower it.
// With `transitions`, the transitions search over the grid's range is
// counted too (TransitionsWork).
void CheckSweepWork(const AnalysisBasis& b, double from, double step, long count, const std::vector<int>& impacts,
                    const std::string& field, bool transitions = false);


}  // namespace nsmodal
