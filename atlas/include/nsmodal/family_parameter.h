#pragma once
// The free (e = 1) 1-impact family's special points followed in a parameter
// of the system (issue 26): how its transitions (singular, modal, grazing:
// the ends of the admissible zones) and its stability changes (a multiplier
// pair through +1 or -1) move with a mass, a spring or a gap. No I/O.
//
// At each value of the parameter the family is swept over the period grid
// and its transitions located as `orbits` locates them (SweepTransitions:
// each refined to ~1e-15 in T, not to the grid), on the model rebuilt with
// that value, with the bridges found at its grazing transitions and period
// doublings (FindBridgeAt, FindPeriodDoublingBridge; one contact). Consecutive values' points of the same kind are linked into
// tracks by the nearest period (within the larger of 5 % of T and three
// grid steps);
// a point with no such neighbour starts a track of its own.
//
// Scaling (DESIGN.md): with one contact and no force, the orbit of gap d is
// the orbit of gap 1 scaled by d, so the gap moves no transition in T and
// multiplies every energy by (d / d0)^2. A gap is not swept: the family at
// the model's own gap is, once, and rescaled (FamilyContinuation::scaled).
#include <functional>
#include <string>
#include <vector>

#include "nsmodal/atlas.h"
#include "nsmodal/parameter.h"
#include "nsmodal/transitions.h"

namespace nsmodal {

// A special point of the family at one value of the parameter: a
// transition or stability change (transitions.h), or a bridge (bridge.h:
// kind "bridge", its period, its continuum's lowest energy).
struct FamilyRow {
  double parameter = 0.0;
  double period = 0.0;
  std::string kind;  // ToString(TransitionKind), or "bridge"
  double energy = 0.0;  // inf at a singular transition
  int contact = 0;      // 0-based
  int track = 0;        // 0-based
};

struct FamilyContinuation {
  std::vector<FamilyRow> rows;  // value by value, each value's points by T
  int tracks = 0;
  bool scaled = false;  // a gap: computed once and rescaled
  std::vector<std::string> notes;
};

// `values`: the parameter's values (from:to:step); `periods`: the family's
// period grid. Throws InputError naming `field` ("parameter") for a
// parameter that does not change the free family (a restitution, a damping,
// the forcing: the family is the conservative twin's), `range` for a range
// that is not FROM:TO:STEP, the scene's field for a value that leaves the
// valid model (a negative mass: WithParameter's error), and `period_field`
// for the period grid (and CheckSweepWork's bound).
// FollowFamily's checks alone, before any work or file (the same errors).
void CheckFamilyRequest(const Model& model, const ModelParameter& parameter, const PeriodGrid& values,
                        const PeriodGrid& periods, const std::string& field = "parameter",
                        const std::string& range = "range", const std::string& period_field = "period");
FamilyContinuation FollowFamily(const Model& model, const ModelParameter& parameter, const PeriodGrid& values,
                                const PeriodGrid& periods, const std::function<void(long, long)>& progress = {},
                                const std::string& field = "parameter", const std::string& range = "range",
                                const std::string& period_field = "period");

}  // namespace nsmodal
