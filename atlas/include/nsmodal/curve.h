#pragma once
// Codimension-two curves (issue 26): a fold, period doubling or grazing of a
// forced response followed in two parameters of the scene at once. No I/O.
//
// The extended system: X = (u, lambda_1, lambda_2), the response problem's
// k unknowns and the two parameters (scaled as response.h scales them),
//   F(X) = [H(u; lambda); g(u; lambda)] = 0,
// H the k impact conditions, g the point's defining condition:
//   fold             det dH/du (the orbit's Jacobian singular: a fold in
//                    either parameter);
//   period-doubling  prod (1 + mu_i) (a real multiplier at -1);
//   grazing          max_interior_gap / d (an interior maximum of a
//                    contact's n.x at its wall; with impacts = 0, the linear
//                    response touching the wall).
// k + 1 equations in k + 2 unknowns: a curve, followed by pseudo-arclength
// (tracer.h's corrector) through the window first_range x second_range.
//
// Starts: the response followed in the first parameter (ComputeResponse) at
// `seeds` values of the second evenly over its range (ends included), then
// in the second at `seeds` values of the first; each special point of the
// followed kind not on a curve already traced starts a curve, followed both
// ways to the window's edge (solved on it), to its start (a closed curve),
// until it stalls where its condition is not smooth (two interior maxima
// exchanging), or until lost. A curve that crosses none of those lines is
// not found.
//
// Along each curve the points where it meets another special point's curve
// are located (Brent on the test function between two points, as response.h
// does): a fold ("fold"; not on a fold curve), a period doubling, a grazing,
// a zero-velocity impact, and on a fold curve its cusps ("cusp": the curve's
// direction in the parameter plane reverses).
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "nsmodal/atlas.h"
#include "nsmodal/field_names.h"
#include "nsmodal/forced_orbit.h"
#include "nsmodal/model.h"
#include "nsmodal/parameter.h"

namespace nsmodal {

enum class CurveKind { kFold, kPeriodDoubling, kGrazing };
// fold, period-doubling, grazing
std::string ToString(CurveKind kind);

struct CurveOptions {
  int impacts = 1;             // m (0: the linear response; grazing only)
  std::vector<int> sequence;   // the contact of each impact (0-based); empty: contact 1
  int periods = 1;             // n
  ModelParameter first, second;
  PeriodGrid first_range, second_range;  // from, to, and the largest step in each
  CurveKind follow = CurveKind::kFold;
  int seeds = 3;               // lines searched for starts, per parameter
  long max_steps = 20000;      // steps per curve and direction
  int max_curves = 32;
  std::function<void(long done, long count)> progress;  // seed lines searched
};

struct CurvePoint {
  int curve = 0;       // 0-based
  std::string kind;    // the followed kind, or where the curve meets another (see above)
  double first = 0.0, second = 0.0;
  ForcedOrbit orbit;
  std::optional<double> condition;  // the followed defining condition g there (nullopt: undefined)
};

struct CurveSet {
  std::vector<CurvePoint> rows;   // curve by curve, in order along each
  std::vector<std::string> ends;  // how each curve ended
  std::vector<std::string> notes; // bounds hit, points not located
  int curves = 0;
};

CurveSet FollowCurves(const Model& model, const CurveOptions& options);

// The point of the curve through `near` (a row of FollowCurves) where the
// second parameter is `second`: Newton on the extended system with the
// second parameter held, from near's orbit. nullopt when it does not
// converge (no point of that curve nearby).
std::optional<CurvePoint> CurvePointAt(const Model& model, const CurveOptions& options, const CurvePoint& near,
                                       double second);

// A curve request as the faces take it (the CLI's continue --second, Python's
// follow_curve): parameters by name (ParseModelParameter), ranges
// "FROM:TO[:STEP]" (STEP (TO - FROM) / 300 by default), `follow` one of
// fold|period-doubling|grazing. Throws InputError naming, through `names`,
// "parameter", "range", "second", "second_range", "follow", "impacts",
// "periods", "sequence", or the scene's field where a corner of the window
// leaves the valid model.
CurveOptions MakeCurveRequest(const Model& model, const std::string& parameter, const std::string& range,
                              const std::string& second, const std::string& second_range, const std::string& follow,
                              int impacts, int periods, const FieldNames& names = FieldNames(),
                              const std::optional<std::string>& sequence = std::nullopt);

}  // namespace nsmodal
