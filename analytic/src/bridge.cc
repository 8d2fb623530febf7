#include "nsmodal/bridge.h"

#include <cmath>
#include <limits>

#include "nsmodal/admissibility.h"
#include "nsmodal/error.h"
#include "nsmodal/flow.h"
#include "nsmodal/model.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/return_map.h"

namespace nsmodal {
namespace {

bool AdmissibleAt(const ModalBasis& b, const Bridge& br, double s) { return BridgeOrbit(b, br, s).admissible; }

}  // namespace

Orbit BridgeOrbit(const ModalBasis& b, const Bridge& bridge, double s) {
  return EvaluateOrbit(b, bridge.y_graze + s * bridge.direction, {bridge.graze_time}, bridge.period);
}

Bridge BridgeAt(const ModalBasis& b, double grazing_period) {
  const Orbit one = OneImpactOrbit(b, grazing_period);
  const SegmentCheck seg = CheckSegment(b, one.y0, grazing_period);
  // A grazing orbit reaches d at an interior maximum; 1e-9 d leaves room for
  // the transition's own error (~1e-15 in T, quadratic in the excess).
  if (!one.potential || !(std::abs(seg.max_excess) <= 1e-9 * b.gap)) {
    throw InputError("period", "T = " + FormatValue(grazing_period) +
                                   " is not a grazing transition of the 1-ipp family (largest interior x_c - d = " +
                                   FormatValue(seg.max_excess) + ")");
  }
  Bridge br;
  br.period = grazing_period;
  br.graze_time = seg.t_at_max;
  br.y_graze = one.y0;

  // ker A_2(t_g, T_G): the two smallest right singular vectors; k is the
  // combination with x_c = 0.
  const int dim = 2 * b.n;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(MatrixA(b, {br.graze_time}, br.period), Eigen::ComputeFullV);
  const Eigen::VectorXd k1 = svd.matrixV().col(dim - 1);
  const Eigen::VectorXd k2 = svd.matrixV().col(dim - 2);
  const double c1 = ContactPosition(b, k1), c2 = ContactPosition(b, k2);
  br.direction = (c2 * k1 - c1 * k2).normalized();
  Eigen::VectorXd flown = br.direction;
  Flow(b, br.graze_time, flown);
  br.degeneracy_residual = std::abs(ContactPosition(b, flown));

  // Which side is admissible: probe at 1e-3 |y_G| (the NC3 excess on the wrong
  // side grows as s^2 ~ 1e-6, far above the admissibility tolerance 1e-10).
  const double scale = br.y_graze.norm();
  const double probe = 1e-3 * scale;
  const bool plus = AdmissibleAt(b, br, probe), minus = AdmissibleAt(b, br, -probe);
  if (plus == minus) {
    throw InputError("period", "T = " + FormatValue(grazing_period) + ": the continuum of 2-ipp orbits at the graze t = " +
                                   FormatValue(br.graze_time) + " is admissible on " + (plus ? "both sides" : "neither side") +
                                   " of the grazing orbit; no bridge");
  }
  if (minus) br.direction = -br.direction;

  // March to the first non-admissible s (steps of |y_G| / 256; E grows as s^2,
  // so 1e3 |y_G| means a million times the grazing energy: unbounded), then
  // bisect the boundary to round-off.
  const double step = scale / 256.0;
  double lo = probe, hi = std::numeric_limits<double>::infinity();
  for (double s = probe + step; s <= 1e3 * scale; s += step) {
    if (!AdmissibleAt(b, br, s)) {
      hi = s;
      break;
    }
    lo = s;
  }
  if (std::isinf(hi)) {
    throw InputError("period", "T = " + FormatValue(grazing_period) + ": the bridge stays admissible up to s = " +
                                   FormatValue(lo) + " (energy " + FormatValue(BridgeOrbit(b, br, lo).energy) + "); unbounded");
  }
  for (int i = 0; i < 200 && hi - lo > 4 * std::numeric_limits<double>::epsilon() * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (AdmissibleAt(b, br, mid) ? lo : hi) = mid;
  }
  br.s_end = lo;
  // The boundary is either an interior maximum reaching d (found above to the
  // NC3 tolerance, whose excess grows as (s - s_end)^2: ~1e-5 relative) or the
  // impact at t = 0 becoming a graze, v_c(0+) = 0: linear in s, so solved
  // exactly. The bisection lands within ~sqrt(1e-10) of the latter.
  const double s_v = -ContactVelocity(b, br.y_graze) / ContactVelocity(b, br.direction);
  if (std::abs(s_v - br.s_end) <= 1e-3 * br.s_end && AdmissibleAt(b, br, s_v)) br.s_end = s_v;

  const double e0 = Energy(br.y_graze), e1 = BridgeOrbit(b, br, br.s_end).energy;
  const double vertex = -br.y_graze.dot(br.direction);
  br.energy_min = std::min(e0, e1);
  br.energy_max = std::max(e0, e1);
  if (vertex > 0.0 && vertex < br.s_end) br.energy_min = std::min(br.energy_min, Energy(br.y_graze + vertex * br.direction));
  return br;
}

}  // namespace nsmodal
