#include "nsmodal/work.h"

#include <algorithm>
#include <cmath>

#include "nsmodal/error.h"

namespace nsmodal {
namespace {

// Roots the searches of the m-ipp orbits of period T isolate (work.h).
double RootsAt(const ModalBasis& b, double period, int impacts) {
  const double h = HalfOscillations(b, period);
  return impacts == 1 ? h : h * (1.0 + h);
}

}  // namespace

double HalfOscillations(const ModalBasis& b, double duration) {
  const double w_max = b.omega.size() > 0 ? b.omega.maxCoeff() : 0.0;
  return w_max * duration / M_PI + 2.0;
}

double SweepWork(const AnalysisBasis& b, double from, double step, long count, int impacts) {
  // A sum over at most PeriodGrid::kMaxPeriods periods: milliseconds.
  double roots = 0.0;
  for (long j = 0; j < count; ++j) roots += RootsAt(b, from + j * step, impacts);
  return roots * (b.n + kRootOverhead);
}

double TransitionsWork(const AnalysisBasis& b, double from, double to) {
  double specials = 0.0;
  const Eigen::VectorXd periods = b.Periods();
  for (int i = 0; i < b.n; ++i) specials += 2.0 * (std::floor(to / periods[i]) - std::floor(from / periods[i]));
  return 4.0 * specials * HalfOscillations(b, to) * (b.n + kRootOverhead);
}

void CheckSweepWork(const AnalysisBasis& b, double from, double step, long count, const std::vector<int>& impacts,
                    const std::string& field, bool transitions) {
  const double to = from + (count - 1) * step;
  double work = 0.0;
  for (int m : impacts) work += SweepWork(b, from, step, count, m);
  const double transition_work = transitions && count > 1 ? TransitionsWork(b, from, to) : 0.0;
  work += transition_work;
  if (work <= kMaxSweepWork) return;
  const bool two = std::find(impacts.begin(), impacts.end(), 2) != impacts.end();
  std::string family = two ? (impacts.size() > 1 ? "1- and 2-ipp orbits" : "2-ipp orbits") : "1-ipp orbits";
  std::string msg = family + " over " + std::to_string(count) + (count == 1 ? " period" : " periods") + " up to T = " +
                    FormatEstimate(to) + " with w_max = " + FormatEstimate(b.omega.maxCoeff()) + " and " + std::to_string(b.n) +
                    (b.n == 1 ? " mode" : " modes") + ": " + FormatEstimate(HalfOscillations(b, to) / 2.0) +
                    " fastest-mode oscillations per period; the searches isolate about ";
  double roots = 0.0;
  for (int m : impacts) roots += SweepWork(b, from, step, count, m) / (b.n + kRootOverhead);
  msg += FormatEstimate(roots) + " roots";
  if (transition_work > 0.0) {
    msg += ", and the transitions search probes about " +
           FormatEstimate(transition_work / (4.0 * HalfOscillations(b, to) * (b.n + kRootOverhead))) +
           " modal and singular periods in the range, " + FormatEstimate(transition_work) + " mode-root evaluations";
  }
  if (two) msg += " (the 2-ipp sweep checks each of its ~" + FormatEstimate(HalfOscillations(b, to)) +
                  " orbits per period over the whole period: quadratic in w_max T)";
  msg += ", an estimated work of " + FormatEstimate(work) + " mode-root evaluations; the limit is " + FormatEstimate(kMaxSweepWork) +
         ": use shorter periods, fewer periods (a larger STEP or a shorter range)" +
         std::string(b.n > 1 ? ", or fewer modes (--modes)" : "");
  throw InputError(field, msg);
}

}  // namespace nsmodal
