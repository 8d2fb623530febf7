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
//                   (Brent's minimiser on -energy; lambda to ~1e-10).
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

namespace nsmodal {

enum class ResponseParameter { kFrequency, kAmplitude };

struct ResponseOptions {
  int impacts = 1;  // m (0: the linear response)
  int periods = 1;  // n
  ResponseParameter parameter = ResponseParameter::kFrequency;
  PeriodGrid grid;  // values of the parameter (w, or a)
  double fixed = 0.0;  // the other one: a when sweeping w, w when sweeping a
  // Bounds: continuation steps per branch, and branches.
  long max_steps = 200000;
  int max_branches = 64;
  std::function<void(long done, long count)> progress;  // grid values scanned

  // Throws InputError naming "impacts", "periods", the grid's field
  // ("frequency" or "amplitude") or the fixed parameter's, as `names` says
  // (the CLI: "--impacts", ...).
  void Validate(const FieldNames& names = FieldNames()) const;
};

enum class SpecialKind { kFold, kPeriodDoubling, kGrazing, kZeroVelocity, kPeak };
std::string ToString(SpecialKind kind);  // fold, period-doubling, grazing, zero-velocity, peak

struct SpecialPoint {
  SpecialKind kind;
  int branch = 0;
  ForcedOrbit orbit;  // at the point (frequency, amplitude, energy, ...)
};

struct ResponseBranch {
  std::vector<ForcedOrbit> points;  // in continuation order
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

// The twin's 1-ipp nonsmooth mode over frequencies w = 2 pi / T in
// [w_from, w_to] (T on a grid of `points` periods), with stability.
Sweep BackboneSweep(const Model& model, double w_from, double w_to, long points, const SweepOptions& options = {});

// The frequency 2 pi / T of the twin's admissible 1-ipp orbit with mean
// energy `energy`, nearest to `near`: Brent on E(T) - energy between the two
// neighbouring sweep orbits that bracket it. nullopt when no admissible
// stretch of the sweep reaches that energy.
std::optional<double> BackboneFrequency(const Model& model, const Sweep& backbone, double energy, double near);

}  // namespace nsmodal
