#pragma once
// Bridges between nonsmooth modes (paper section 4, Figs. 13-15): continua of
// 2-ipp orbits of one period, vertical segments in the frequency-energy plot.
//
// At a root (t2, T) of det A_2, ker A_2 has dimension 2 and NC2 asks
// x_c(0) = d and x_c(t2) = d of y0 in it. When the two conditions coincide,
// NC2 leaves a line of initial states
//   y(s) = y_origin + s k,   k in ker A_2, x_c(k) = 0, |k| = 1,
// every one a potential 2-ipp orbit of the same period, with energy
//   E(s) = E(origin) + s (y_origin . k) + s^2 / 2   (E = |y|^2 / 2, modal_basis.h).
// The admissible ones form an interval [s_begin, s_end] around 0. Two ways to
// such a line are known:
//
// Grazing (BridgeAt). At a grazing transition T_G (transitions.h) the 1-ipp
// orbit y_G touches d at an interior time t_g with zero velocity: a contact
// with no effect, so y_G is also a 2-ipp orbit with t2 = t_g. origin = y_G,
// which is an end: s_begin = 0 (k's sign chosen so). The 1-ipp orbit is
// symmetric, x(t) = x(T - t), so it also grazes at T - t_g; started there it is
// again a 2-ipp orbit with t2 = t_g. On the paper's system (tests) that time
// shift is the far end y(s_end), E(s) is symmetric about s_end / 2, and the
// middle is the lowest-energy orbit of the continuum, on a 2-ipp branch. When
// t_g = T_G / 2 the shift is half a period and the middle is the 1-ipp orbit
// of period T_G / 2 run twice: the bridge joins the 1-ipp branch to its
// factor-2 dilation, the case of the paper (Figs. 13-15).
//
// Period doubling (PeriodDoublingBridge). Where a 1-ipp orbit of period T*
// has its nontrivial Floquet pair at -1 (stability.h) with an eigenvector
// that does not move x_c, the orbit run twice is a 2-ipp orbit (t2 = T*,
// period 2 T*) with coinciding NC2 conditions: origin is that orbit, in the
// interior of its line (s_begin < 0 < s_end). The paper's bridge is also one
// of these (T* = T_G / 2). Where the eigenvector moves x_c the period doubling
// is a pitchfork of the 2-ipp roots instead, and there is no bridge.
//
// Another contact's grazing (several contacts, issue 24) is no bridge: there
// the family of contact j meets the (j, k) family at one orbit, whose two NC2
// conditions, on two walls, stay independent (tests/contacts_test.cc,
// AnotherContactsGrazingIsAJunctionNotABridge). Bridges are contact 1's own.
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "nsmodal/modal_basis.h"
#include "nsmodal/orbit.h"

namespace nsmodal {

enum class BridgeKind { kGrazing, kPeriodDoubling };

struct Bridge {
  BridgeKind kind = BridgeKind::kGrazing;
  double period = 0.0;        // T_G, or 2 T*
  double t2 = 0.0;            // the second impact: t_g, or T*
  Eigen::VectorXd origin;     // y(0): the grazing 1-ipp orbit, or the T* orbit
  Eigen::VectorXd direction;  // k
  double s_begin = 0.0;       // y(s) admissible for s in [s_begin, s_end]
  double s_end = 0.0;
  // |x_c(S(t2) k)| / |k|: how far the two NC2 conditions are from coinciding
  // (round-off level on a true bridge).
  double degeneracy_residual = 0.0;
  double energy_min = 0.0, energy_max = 0.0;  // E over [s_begin, s_end]
};

// Whether a bridge was found, and if not why: a numerical outcome, returned.
enum class BridgeStatus {
  kFound,
  kNotGrazing,     // the 1-ipp orbit has no interior maximum within 1e-9 d of d
  kNotOneSided,    // the continuum is admissible on both sides of the graze, or neither
  kNotAdmissible,  // the 1-ipp orbit at T* is not admissible
  kPitchfork,      // NC2 does not leave a line at 2 T*: a pitchfork of the 2-ipp roots
  kUnbounded,      // admissible to 1e3 times the origin's size
};
struct BridgeSearch {
  BridgeStatus status = BridgeStatus::kFound;
  std::string message;  // why not, naming the period; empty when found
  Bridge bridge;        // meaningful when found()
  bool found() const { return status == BridgeStatus::kFound; }
};

// The bridge at the grazing transition of period `grazing_period` (as found by
// OneImpactTransitions, to ~1e-15).
BridgeSearch FindBridgeAt(const AnalysisBasis& b, double grazing_period);
// The same for a caller that asked for a bridge at a given period: throws
// InputError naming "period" when there is none.
Bridge BridgeAt(const AnalysisBasis& b, double grazing_period);
// Periods T* in [from, to] where an admissible 1-ipp orbit has a Floquet
// multiplier at -1: the kMultiplierMinusOne crossings of
// OneImpactMultiplierCrossings (transitions.h) on that grid.
std::vector<double> OneImpactPeriodDoublings(const AnalysisBasis& b, double from, double to, double step);

// The bridge of period 2 T* through the 1-ipp orbit of period T* run twice:
// kPitchfork when NC2 does not leave a line there, kNotAdmissible when the
// orbit is not admissible.
BridgeSearch FindPeriodDoublingBridge(const AnalysisBasis& b, double doubling_period);
// Throwing form, as BridgeAt.
Bridge PeriodDoublingBridge(const AnalysisBasis& b, double doubling_period);
// The potential 2-ipp orbit y(s) of the bridge (times {t2}).
Orbit BridgeOrbit(const AnalysisBasis& b, const Bridge& bridge, double s);

}  // namespace nsmodal
