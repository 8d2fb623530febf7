#pragma once
// Speed against accuracy for every integrator, and where each one fails.
//
// Work-precision: each case is integrated by every integrator over a sweep of
// its accuracy setting (exact: root_tol; cvode: its relative tolerance, Adams and BDF;
// moreau-jean: step h). The error is the relative distance of the final state
// to the exact integrator at its tightest setting; the cost is the thread's
// CPU time. Cases (the paper's system unless said):
//   smooth       a stable 1-ipp orbit (T = 7.5), 10 periods;
//   near-grazing the admissible 1-ipp orbit 1e-3 from the grazing transition
//                T_G ~ 9.127 (x_c peaks 3.5e-3 below d between impacts), 3 periods;
//   high-energy  the 1-ipp orbit 0.01 above the singular transition T_S ~ 4.834 (E ~ 4e4), 3 periods;
//   long         the stable orbit of `smooth` over 10,000 periods;
//   zeno         e = 0.5, an accumulation of impacts, sticking and release, t in [0, 1].
//
// Grazing failures: orbits at T_G - delta (admissible: x_c peaks delta-close
// below d between impacts) and T_G + delta (a short excursion above d), one
// period each: every integrator's impact count against the exact one. An
// integrator duplicates impacts when its error exceeds the clearance, and
// misses the excursion when it is shallower than what it resolves.
#include <functional>
#include <string>
#include <vector>

#include "nsmodal/model.h"

namespace nsmodal {

struct WorkPrecisionRow {
  std::string case_name, integrator, setting;
  double setting_value = 0.0;
  double error = 0.0;
  double cpu_s = 0.0;
  long impacts = 0;
  long steps = 0;
  long expected_impacts = 0;  // the reference run's (exact, root_tol 1e-14)
  // The reference run is Zeno (impacts accumulate and are truncated at
  // zeno_flight): its impact count depends on the truncation, not a check.
  bool zeno = false;
};

struct GrazingRow {
  double delta = 0.0;
  std::string side;  // "below" (admissible) or "above" (excursion)
  std::string integrator, setting;
  long impacts = 0;           // first period
  long expected_impacts = 0;  // the exact integrator's count
  double clearance = 0.0;     // max x_c - d between impacts (negative below)
};

struct WorkPrecisionOptions {
  bool quick = false;  // fewer settings and a 100-period long case (tests, CI)
  int threads = 0;     // 0: all cores
  std::function<void(long, long)> progress;  // (done, total), from the calling thread
};

// Per integrator setting: the shallowest excursion above d that it still
// turns into the right impacts, and the smallest clearance below d that it
// still respects (no spurious impact), each the limit down to which every
// larger delta was right too (the smallest tried when right at every one;
// inf when wrong at the largest).
struct GrazingLimit {
  std::string integrator, setting;
  double shallowest_excursion = 0.0;
  double smallest_clearance = 0.0;
};
std::vector<GrazingLimit> SummarizeGrazing(const std::vector<GrazingRow>& rows);

// The cases are defined on the paper's system (PaperModel: a stable orbit
// at T = 7.5, the grazing and singular transitions at 9.127 and 4.834, a
// Zeno start): InputError naming `field` for a model with another M, K,
// contact or gap.
void CheckBenchModel(const Model& model, const std::string& field = "scene");

std::vector<WorkPrecisionRow> RunWorkPrecision(const WorkPrecisionOptions& options = {});
std::vector<GrazingRow> RunGrazingFailures(const WorkPrecisionOptions& options = {});

}  // namespace nsmodal
