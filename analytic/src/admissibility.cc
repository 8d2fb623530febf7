#include "nsmodal/admissibility.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "nsmodal/flow.h"
#include "nsmodal/roots.h"

namespace nsmodal {

SegmentCheck CheckSegment(const AnalysisBasis& b, const Eigen::Ref<const Eigen::VectorXd>& y, double duration) {
  const ContactSignal f(b, y);
  SegmentCheck out{-std::numeric_limits<double>::infinity(), 0.0, f.Velocity(0.0), f.Velocity(duration), 0.0,
                   0.0, true};
  out.position_scale = f.bound[0];
  out.velocity_scale = f.bound[1];
  // Tangencies of v_c (inflections of x_c at zero slope) resolved to 1e-12 of the segment.
  // Work limit from the problem's scale: v_c has about w_max duration / pi
  // roots, each isolated in ~40 halvings.
  const double w_max = f.omega.size() > 0 ? f.omega.maxCoeff() : 0.0;
  const long max_cells = static_cast<long>(std::min(1e9, 1000.0 * (2.0 + w_max * duration / M_PI)));
  const std::vector<double> critical =
      IsolateRoots([&f](double t) { return f.VelocityAcceleration(t); }, f.bound[2], f.bound[3], 0.0, duration,
                   1e-12 * duration, max_cells, &out.complete);
  for (double t : critical) {
    if (t <= 0.0 || t >= duration) continue;
    const double excess = f.Position(t) - b.gap;
    if (excess > out.max_excess) {
      out.max_excess = excess;
      out.t_at_max = t;
    }
  }
  return out;
}

Orbit EvaluateOrbit(const AnalysisBasis& b, const Eigen::VectorXd& y0, const std::vector<double>& times,
                    double period, const AdmissibilityOptions& options) {
  Orbit orbit;
  orbit.impacts = static_cast<int>(times.size()) + 1;
  orbit.period = period;
  orbit.times = times;
  orbit.y0 = y0;
  orbit.z0 = PhysicalOf(b, y0);
  orbit.energy = Energy(y0);
  orbit.max_excess = -std::numeric_limits<double>::infinity();

  std::ostringstream why;
  bool nc3 = true;
  double nc2 = std::abs(ContactPosition(b, y0) - b.gap);
  Eigen::VectorXd y = y0;
  double start = 0.0;
  for (int k = 0; k < orbit.impacts; ++k) {
    const double end = k + 1 < orbit.impacts ? times[k] : period;
    const double duration = end - start;
    const SegmentCheck seg = CheckSegment(b, y, duration);
    const double xtol = options.rel_tol * std::max(b.gap, seg.position_scale);
    const double vtol = options.rel_tol * seg.velocity_scale;
    if (seg.max_excess > orbit.max_excess) orbit.max_excess = seg.max_excess;
    if (nc3 && !seg.complete) {
      why << "NC3 undetermined: the search for maxima of x_c on the flight from t = " << start
          << " hit its work limit";
      nc3 = false;
    } else if (nc3 && seg.max_excess > xtol) {
      why << "NC3: x_c exceeds d by " << seg.max_excess << " at t = " << start + seg.t_at_max;
      nc3 = false;
    } else if (nc3 && seg.start_velocity > vtol) {
      why << "NC3: v_c = " << seg.start_velocity << " > 0 just after the impact at t = " << start;
      nc3 = false;
    } else if (nc3 && seg.end_velocity < -vtol) {
      why << "NC3: v_c = " << seg.end_velocity << " < 0 just before the impact at t = " << end;
      nc3 = false;
    }
    Flow(b, duration, y);
    if (k + 1 < orbit.impacts) nc2 = std::max(nc2, std::abs(ContactPosition(b, y) - b.gap));
    ElasticImpact(b, y);
    start = end;
  }
  orbit.nc2_residual = nc2 / b.gap;
  const Eigen::VectorXd zT = PhysicalOf(b, y);
  orbit.periodicity_residual = (zT - orbit.z0).norm() / orbit.z0.norm();
  orbit.potential = std::isfinite(orbit.energy) && orbit.nc2_residual <= options.potential_tol &&
                    orbit.periodicity_residual <= options.potential_tol;
  if (!orbit.potential) {
    why.str("");
    why << "not potential: NC2 residual " << orbit.nc2_residual << ", periodicity residual "
        << orbit.periodicity_residual;
  }
  orbit.admissible = orbit.potential && nc3;
  orbit.reason = why.str();
  return orbit;
}

}  // namespace nsmodal
