#pragma once
// Frequency-response curves (issue 11): the families of forced periodic
// orbits (forced_orbit.h) followed through the frequency w, or through the
// forcing amplitude a at fixed w, by pseudo-arclength continuation, with their
// special points located on the branch, not on the grid. No I/O.
//
// Continuation: X = (u, lambda), H(X) = the m impact conditions; the tangent
// t spans the kernel of dH/dX (central differences), the predictor steps h
// along t, the corrector is Newton on [H(X); t'(X - X_pred)] = 0 (so folds
// are passed); h halves on a failed corrector and grows by 1.5 after a quick
// one, at most `step` in lambda per point. Coordinates are scaled (phase by
// 2 pi, durations by the period, lambda by the range) so that one h means
// the same everywhere. Every grid value of lambda crossed gets a point of its
// own (a Newton solve at that lambda), and at each grid value ForcedProblem::
// FindAll looks for solutions no branch has reached yet (isolas, branches born
// inside the range): each starts a branch followed both ways.
//
// Special points, located by Brent's method on a test function along the
// branch (a segment between two points, re-solved on the hyperplanes normal
// to its chord) to ~1e-12 in lambda:
//   fold            the lambda-component of the tangent changes sign;
//   period-doubling a real multiplier crosses -1: prod(1 + mu_i) changes sign;
//   grazing         an interior maximum of x_c reaches d (admissibility ends,
//                   a family with more impacts takes over);
//   zero-velocity   an impact velocity v_c(t_i-) reaches 0;
//   peak            the largest energy of an admissible stretch of a branch
//                   (Brent's minimiser on -energy; lambda to ~1e-10);
//   torus           a complex pair of multipliers crosses the unit circle
//                   (Neimark-Sacker): prod over the complex pairs of
//                   (|mu|^2 - 1) changes sign, the number of pairs the same
//                   at both ends.
// For m = 0 (the linear, non-impacting response, in closed form at each grid
// value) the grazing points (max x_c = d) and the peaks are located alike.
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

// What a response is followed in: the forcing frequency w, its amplitude a,
// or any scalar parameter of the model (issue 26: parameter.h, the others
// held; w and a are then the model's own at each value).
enum class ResponseParameter { kFrequency, kAmplitude, kModel };

struct ResponseOptions {
  int impacts = 1;  // m (0: the linear response)
  // The contact of each impact (0-based, issue 24), `impacts` entries; empty:
  // every impact on contact 1.
  std::vector<int> sequence;
  int periods = 1;  // n
  ResponseParameter parameter = ResponseParameter::kFrequency;
  PeriodGrid grid;  // values of the parameter (w, a, or the model's parameter)
  double fixed = 0.0;  // the other one: a when sweeping w, w when sweeping a (unused for kModel)
  // kModel: the parameter (ParseModelParameter of the model the response is
  // computed for). Its grid may start at 0 (a damping ratio, e); the model
  // at both ends must be valid.
  std::optional<ModelParameter> model_parameter;
  // Bounds: continuation steps per branch, and branches.
  long max_steps = 200000;
  int max_branches = 64;
  std::function<void(long done, long count)> progress;  // grid values scanned

  // Throws InputError naming "impacts", "periods", the grid's field
  // ("frequency" or "amplitude"; "range" for kModel) or the fixed
  // parameter's, as `names` says (the CLI: "--impacts", ...).
  void Validate(const FieldNames& names = FieldNames()) const;
  // The parameter's name in messages and columns: "w", "a", or the model
  // parameter's as written ("masses[1]").
  std::string ParameterName() const;
};

enum class SpecialKind { kFold, kPeriodDoubling, kGrazing, kZeroVelocity, kPeak, kTorus };
// fold, period-doubling, grazing, zero-velocity, peak, torus
std::string ToString(SpecialKind kind);

struct SpecialPoint {
  SpecialKind kind;
  int branch = 0;
  ForcedOrbit orbit;  // at the point (frequency, amplitude, energy, ...)
  double parameter = 0.0;  // the followed parameter's value there
};

struct ResponseBranch {
  std::vector<ForcedOrbit> points;  // in continuation order
  std::vector<double> parameter;    // the followed parameter's value at each point
  std::string end;                  // how the branch ended
};

struct ResponseCurve {
  ResponseOptions options;
  std::vector<ResponseBranch> branches;
  std::vector<SpecialPoint> points;
  std::vector<std::string> notes;  // bounds hit, branches lost
};

ResponseCurve ComputeResponse(const Model& model, const ResponseOptions& options);

// The backbone: the model's conservative twin (no damping, no force, e = 1),
// whose nonsmooth modes the responses are compared with.
Model ConservativeTwin(const Model& model);

// The twin's nonsmooth mode the responses of `sequence` meet, over
// frequencies w = 2 pi / T in [w_from, w_to] (T on a grid of `points`
// periods), with stability: for a sequence on one contact c (empty: contact
// 1), its 1-ipp mode; for (a, b), two different contacts, the symmetric
// member of the (a, b) family, t2 = T/2 (always a root of the two-contact
// closed form, two_impact.h): one orbit per period in either case.
Sweep BackboneSweep(const Model& model, double w_from, double w_to, long points, const SweepOptions& options = {},
                    const std::vector<int>& sequence = {});

// The frequency 2 pi / T of the twin's admissible 1-ipp orbit with mean
// energy `energy`, nearest to `near`: Brent on E(T) - energy between the two
// neighbouring sweep orbits that bracket it. nullopt when no admissible
// stretch of the sweep reaches that energy.
std::optional<double> BackboneFrequency(const Model& model, const Sweep& backbone, double energy, double near,
                                        const std::vector<int>& sequence = {});

// A response request as the faces take it: the parameter `swept` over
// `grid`, the other one held at each of `levels` (none given: the model's
// own, max |f_i| of its force beside a frequency grid, 0 without one, its w
// beside an amplitude grid), m = impacts, n = periods. The options hold the
// first level, checked (ResponseOptions::Validate(names)).
struct ResponseRequest {
  ResponseOptions options;
  std::vector<double> levels;
};
// `sequence`: the contacts of the impacts as text ("1,2", the CLI's
// --sequence), checked against the model's contacts; it sets m (impacts must
// then be 1, its default, or the sequence's length).
ResponseRequest MakeResponseRequest(const Model& model, ResponseParameter swept, const PeriodGrid& grid,
                                    std::vector<double> levels, int impacts, int periods,
                                    const FieldNames& names = FieldNames(),
                                    const std::optional<std::string>& sequence = std::nullopt);

// A continuation request (issue 26: `nsmodal continue`, Python's
// continue_parameter): the response of `impacts` impacts (or `sequence`) in
// `periods` forcing periods followed in the parameter `parameter`
// (ParseModelParameter: "gap", "masses[1]", ...; frequency and amplitude
// followed as `response` follows them, the other held at the model's) over
// `range`, "FROM:TO" or "FROM:TO:STEP" (STEP, the largest step and the
// spacing of the points solved at fixed values: (TO - FROM) / 300 by
// default). Throws InputError naming, through `names`, "parameter", "range",
// "impacts", "periods", "sequence", or the scene's field when the model at
// an end of the range is not valid; "forcing.amplitude" for a model without
// a harmonic force.
ResponseRequest MakeContinuationRequest(const Model& model, const std::string& parameter, const std::string& range,
                                        int impacts, int periods, const FieldNames& names = FieldNames(),
                                        const std::optional<std::string>& sequence = std::nullopt);

// The same with the parameter and range parsed (`range` checked here).
ResponseRequest MakeContinuationRequest(const Model& model, const ModelParameter& parameter, const PeriodGrid& range,
                                        int impacts, int periods, const FieldNames& names = FieldNames(),
                                        const std::optional<std::string>& sequence = std::nullopt);
// A parameter's range as `continue` reads it: "FROM:TO" or "FROM:TO:STEP"
// (plain numbers; STEP (TO - FROM) / 300 by default). Throws InputError
// naming `field` for any other text; the values are checked by the request.
PeriodGrid ParseParameterRange(const std::string& text, const std::string& field);
// A model parameter's range checked: finite, TO > FROM, STEP > 0 (FROM may
// be 0 or negative: the model's own checks say which values are valid), at
// most PeriodGrid::kMaxPeriods values. Throws InputError naming `field`.
void CheckParameterRange(const PeriodGrid& range, const std::string& field);

// A point of a response with the number of its branch (1-based): a row of
// response.csv (report/tables.h), of Python's response()["rows"].
struct ResponseRow {
  int branch = 0;
  ForcedOrbit orbit;
  double parameter = 0.0;  // the followed parameter's value (w, a, or the model's)
};

// The curves of one grid at each value of the fixed parameter (the CLI's
// --amplitude 0.1,0.3 beside a frequency grid; one value from Python),
// merged: the branches numbered on from one level to the next.
struct ResponseLevels {
  std::vector<ResponseRow> rows;      // every branch's points, branch by branch
  std::vector<SpecialPoint> points;   // every curve's; branch: 0-based over the merged branches
  std::vector<std::string> ends;      // how each merged branch ended
  std::vector<std::string> notes;     // every curve's
  int branches = 0;
};
// `options` at each of `levels` in turn (its `fixed` replaced); progress(level)
// gives each curve's progress callback (empty: none), on_curve(curve,
// first_branch) is called as each curve is done (first_branch: the merged
// 0-based number of its first branch).
ResponseLevels ComputeResponseLevels(
    const Model& model, const ResponseOptions& options, const std::vector<double>& levels,
    const std::function<std::function<void(long, long)>(double level)>& progress = {},
    const std::function<void(const ResponseCurve& curve, int first_branch)>& on_curve = {});

// The backbone beside a frequency response and the peaks matched to it: the
// conservative twin's 1-ipp mode over the grid's frequencies divided by n
// (an (m, n) response meets the mode of frequency w / n; BackboneSweep of
// 2000 periods, stability of the admissible orbits) and, at each peak of
// `points`, the mode's frequency at the peak's energy nearest to the
// response's own w / n (BackboneFrequency).
struct BackboneMatch {
  Sweep backbone;
  // One per point: the mode's frequency at a peak; nullopt at the other
  // points and where no admissible stretch of the mode reaches the energy.
  std::vector<std::optional<double>> mode_frequency;
};
// Why a response has no backbone (nullopt: it has one): its sequence is
// neither on one contact nor two different contacts once each, or the model
// has a rigid-body mode (an impact damper: its conservative twin has no
// analysis basis).
std::optional<std::string> NoBackbone(const Model& model, const ResponseOptions& options);
// (Requires !NoBackbone(model, options).)
BackboneMatch MatchBackbone(const Model& model, const ResponseOptions& options, const std::vector<SpecialPoint>& points,
                            const std::function<void(long done, long count)>& progress = {});

}  // namespace nsmodal
