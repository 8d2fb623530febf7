#include "nsmodal/bridge.h"

#include <cmath>
#include <limits>

#include "nsmodal/admissibility.h"
#include "nsmodal/error.h"
#include "nsmodal/flow.h"
#include "nsmodal/model.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/transitions.h"
#include "nsmodal/return_map.h"
#include "nsmodal/roots.h"
#include "nsmodal/stability.h"
#include "nsmodal/stop.h"

namespace nsmodal {
namespace {

bool AdmissibleAt(const AnalysisBasis& b, const Bridge& br, double s) { return BridgeOrbit(b, br, s).admissible; }

// k in ker A_2(t2, T) with x_c(k) = 0, |k| = 1, and the degeneracy residual.
void LineDirection(const AnalysisBasis& b, Bridge& br) {
  const int dim = 2 * b.n;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(MatrixA(b, {br.t2}, br.period), Eigen::ComputeFullV);
  const Eigen::VectorXd k1 = svd.matrixV().col(dim - 1);
  const Eigen::VectorXd k2 = svd.matrixV().col(dim - 2);
  const double c1 = ContactPosition(b, k1), c2 = ContactPosition(b, k2);
  br.direction = (c2 * k1 - c1 * k2).normalized();
  Eigen::VectorXd flown = br.direction;
  Flow(b, br.t2, flown);
  br.degeneracy_residual = std::abs(ContactPosition(b, flown));
}

// The last admissible s from `from` (admissible) going in the direction of
// `probe` (sign), in steps of `step`, then bisected to round-off. Infinite if
// still admissible at 1e3 |origin| (energy a million times the origin's).
double AdmissibleExtent(const AnalysisBasis& b, const Bridge& br, double from, double step) {
  const double limit = 1e3 * br.origin.norm();
  double lo = from, hi = std::numeric_limits<double>::infinity();
  for (double s = from + step; std::abs(s) <= limit; s += step) {
    if (!AdmissibleAt(b, br, s)) {
      hi = s;
      break;
    }
    lo = s;
  }
  if (std::isinf(hi)) return std::copysign(std::numeric_limits<double>::infinity(), step);
  for (int i = 0; i < 200 && std::abs(hi - lo) > 4 * std::numeric_limits<double>::epsilon() * std::abs(hi); ++i) {
    const double mid = 0.5 * (lo + hi);
    (AdmissibleAt(b, br, mid) ? lo : hi) = mid;
  }
  // The boundary is either an interior maximum reaching d (found above to the
  // NC3 tolerance, whose excess grows as (s - s_end)^2: ~1e-5 relative) or an
  // impact becoming a graze, v_c = 0 just after the impact at 0 or just before
  // the one at t2: linear in s, so solved exactly. The bisection lands within
  // ~sqrt(1e-10) of such a root.
  Eigen::VectorXd o2 = br.origin, k2 = br.direction;
  Flow(b, br.t2, o2);
  Flow(b, br.t2, k2);
  for (double s_v : {-ContactVelocity(b, br.origin) / ContactVelocity(b, br.direction),
                     -ContactVelocity(b, o2) / ContactVelocity(b, k2)}) {
    if (std::abs(s_v - lo) <= 1e-3 * std::abs(lo) && AdmissibleAt(b, br, s_v)) return s_v;
  }
  return lo;
}

void Energies(const AnalysisBasis& b, Bridge& br) {  // b elastic: E(s) is quadratic, vertex below
  const auto energy = [&](double s) { return Energy(b, br.origin + s * br.direction); };
  br.energy_min = std::min(energy(br.s_begin), energy(br.s_end));
  br.energy_max = std::max(energy(br.s_begin), energy(br.s_end));
  const double vertex = -br.origin.dot(br.direction);
  if (vertex > br.s_begin && vertex < br.s_end) br.energy_min = std::min(br.energy_min, energy(vertex));
}

BridgeSearch NotFound(BridgeStatus status, std::string message) { return {status, std::move(message), {}}; }

// The ends are known: bounded, with its energies, or unbounded.
BridgeSearch Finish(const AnalysisBasis& b, Bridge br) {
  if (std::isinf(br.s_begin) || std::isinf(br.s_end)) {
    return NotFound(BridgeStatus::kUnbounded, "T = " + FormatValue(br.period) +
                                                  ": the continuum of 2-ipp orbits stays admissible to 1e3 times "
                                                  "the origin's size; unbounded");
  }
  Energies(b, br);
  return {BridgeStatus::kFound, "", std::move(br)};
}

Bridge OrThrow(BridgeSearch search) {
  if (!search.found()) throw InputError("period", search.message);
  return std::move(search.bridge);
}

}  // namespace

Orbit BridgeOrbit(const AnalysisBasis& b, const Bridge& bridge, double s) {
  return EvaluateOrbit(b, bridge.origin + s * bridge.direction, {bridge.t2}, bridge.period);
}

Bridge BridgeAt(const AnalysisBasis& b, double grazing_period) { return OrThrow(FindBridgeAt(b, grazing_period)); }

Bridge PeriodDoublingBridge(const AnalysisBasis& b, double doubling_period) {
  return OrThrow(FindPeriodDoublingBridge(b, doubling_period));
}

BridgeSearch FindBridgeAt(const AnalysisBasis& b, double grazing_period) {
  const Orbit one = OneImpactOrbit(b, grazing_period);
  const SegmentCheck seg = CheckSegment(b, one.y0, grazing_period);
  // A grazing orbit reaches d at an interior maximum; 1e-9 d leaves room for
  // the transition's own error (~1e-15 in T, quadratic in the excess).
  if (!one.potential || !(std::abs(seg.max_excess) <= 1e-9 * b.gap)) {
    return NotFound(BridgeStatus::kNotGrazing, "T = " + FormatValue(grazing_period) +
                                   " is not a grazing transition of the 1-ipp family (largest interior x_c - d = " +
                                   FormatValue(seg.max_excess) + ")");
  }
  Bridge br;
  br.kind = BridgeKind::kGrazing;
  br.period = grazing_period;
  br.t2 = seg.t_at_max;
  br.origin = one.y0;
  LineDirection(b, br);

  // Which side is admissible: probe at 1e-3 |y_G| (the NC3 excess on the wrong
  // side grows as s^2 ~ 1e-6, far above the admissibility tolerance 1e-10).
  const double probe = 1e-3 * br.origin.norm();
  const bool plus = AdmissibleAt(b, br, probe), minus = AdmissibleAt(b, br, -probe);
  if (plus == minus) {
    return NotFound(BridgeStatus::kNotOneSided, "T = " + FormatValue(grazing_period) +
                                   ": the continuum of 2-ipp orbits at the graze t = " + FormatValue(br.t2) +
                                   " is admissible on " + (plus ? "both sides" : "neither side") +
                                   " of the grazing orbit; no bridge");
  }
  if (minus) br.direction = -br.direction;
  br.s_begin = 0.0;
  br.s_end = AdmissibleExtent(b, br, probe, br.origin.norm() / 256.0);
  return Finish(b, std::move(br));
}

std::vector<double> OneImpactPeriodDoublings(const AnalysisBasis& b, double from, double to, double step) {
  std::vector<double> periods;
  std::vector<bool> admissible;
  for (long k = 0; from + k * step <= to + 1e-12 * to; ++k) {
    ThrowIfStopRequested();
    periods.push_back(from + k * step);
    admissible.push_back(OneImpactOrbit(b, periods.back()).admissible);
  }
  std::vector<double> out;
  if (periods.size() < 2) return out;
  for (const Transition& t : OneImpactMultiplierCrossings(b, periods, admissible)) {
    if (t.kind == TransitionKind::kMultiplierMinusOne) out.push_back(t.period);
  }
  return out;
}

BridgeSearch FindPeriodDoublingBridge(const AnalysisBasis& b, double doubling_period) {
  const Orbit one = OneImpactOrbit(b, doubling_period);
  if (!one.admissible) {
    return NotFound(BridgeStatus::kNotAdmissible, "T* = " + FormatValue(doubling_period) + ": the 1-ipp orbit is not admissible (" +
                                   one.reason + ")");
  }
  Bridge br;
  br.kind = BridgeKind::kPeriodDoubling;
  br.period = 2.0 * doubling_period;
  br.t2 = doubling_period;
  br.origin = one.y0;
  LineDirection(b, br);
  // A true line has the residual at round-off (measured <= 3e-15); a
  // pitchfork has it O(1) (0.15 at T* = 9.4907 on the paper's system).
  if (!(br.degeneracy_residual <= 1e-9)) {
    return NotFound(BridgeStatus::kPitchfork, "T* = " + FormatValue(doubling_period) +
                                   ": NC2 does not leave a line at 2 T* (residual " +
                                   FormatValue(br.degeneracy_residual) +
                                   "): the period doubling is a pitchfork of the 2-ipp roots, no bridge");
  }
  const double step = br.origin.norm() / 256.0;
  br.s_begin = AdmissibleExtent(b, br, 0.0, -step);
  br.s_end = AdmissibleExtent(b, br, 0.0, step);
  return Finish(b, std::move(br));
}

}  // namespace nsmodal
