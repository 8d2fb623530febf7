#include "nsmodal/admissibility.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>
#include <vector>

#include "nsmodal/flow.h"
#include "nsmodal/check.h"
#include "nsmodal/roots.h"

namespace nsmodal {

SegmentCheck CheckSegment(const AnalysisBasis& b, const Eigen::Ref<const Eigen::VectorXd>& y, double duration) {
  return CheckSegment(b, b.contacts.front(), y, duration);
}

namespace {

// CheckSegment on the signal f = n . x of a flight; its critical points
// (the roots of v_c) isolated here, or taken from `reuse` (those of a
// contact whose r is parallel: the same roots), and left in `critical`.
SegmentCheck CheckSignal(const ContactSignal& f, double gap, double duration, const std::vector<double>* reuse,
                         std::vector<double>& critical) {
  SegmentCheck out{-std::numeric_limits<double>::infinity(), 0.0, f.Velocity(0.0), f.Velocity(duration), 0.0,
                   0.0, true};
  out.position_scale = f.bound[0];
  out.velocity_scale = f.bound[1];
  if (reuse != nullptr) {
    critical = *reuse;
  } else {
    // Tangencies of v_c (inflections of x_c at zero slope) resolved to 1e-12 of the segment.
    // Work limit from the problem's scale: v_c has about w_max duration / pi
    // roots, each isolated in ~40 halvings.
    const double w_max = f.omega.size() > 0 ? f.omega.maxCoeff() : 0.0;
    const long max_cells = static_cast<long>(std::min(1e9, 1000.0 * (2.0 + w_max * duration / M_PI)));
    critical = IsolateRoots([&f](double t) { return f.VelocityAcceleration(t); }, f.bound[2], f.bound[3], 0.0,
                            duration, 1e-12 * duration, max_cells, &out.complete);
  }
  for (double t : critical) {
    if (t <= 0.0 || t >= duration) continue;
    const double excess = f.Position(t) - gap;
    if (excess > out.max_excess) {
      out.max_excess = excess;
      out.t_at_max = t;
    }
  }
  return out;
}

}  // namespace

SegmentCheck CheckSegment(const AnalysisBasis& b, const ModalContact& contact, const Eigen::Ref<const Eigen::VectorXd>& y,
                          double duration) {
  std::vector<double> critical;
  return CheckSignal(ContactSignal(b, contact, y), contact.gap, duration, nullptr, critical);
}

Orbit EvaluateOrbit(const AnalysisBasis& b, const Eigen::VectorXd& y0, const std::vector<double>& times,
                    double period, const AdmissibilityOptions& options, std::vector<int> sequence) {
  Orbit orbit;
  orbit.impacts = static_cast<int>(times.size()) + 1;
  orbit.period = period;
  orbit.times = times;
  if (sequence.empty()) sequence.assign(orbit.impacts, 0);
  NSMODAL_CHECK(static_cast<int>(sequence.size()) == orbit.impacts);
  orbit.sequence = sequence;
  orbit.y0 = y0;
  orbit.z0 = PhysicalOf(b, y0);
  orbit.energy = Energy(b, y0);
  orbit.max_excess = -std::numeric_limits<double>::infinity();
  const int contacts = static_cast<int>(b.contacts.size());
  std::vector<bool> in_sequence(contacts, false);
  for (int j : sequence) in_sequence[j] = true;

  std::ostringstream why;
  bool nc3 = true;
  // Each flight's critical points per contact: a contact whose r is parallel
  // to an earlier one's (two walls of one dof) has the same ones.
  std::vector<std::vector<double>> critical(contacts);
  std::vector<bool> complete(contacts, true);
  const ModalContact& first = b.contacts[sequence[0]];
  double nc2 = std::abs(ContactPosition(b, first, y0) - first.gap) / first.gap;
  Eigen::VectorXd y = y0;
  double start = 0.0;
  for (int k = 0; k < orbit.impacts; ++k) {
    const double end = k + 1 < orbit.impacts ? times[k] : period;
    const double duration = end - start;
    const int from = sequence[k], to = sequence[(k + 1) % orbit.impacts];
    for (int c = 0; c < contacts; ++c) {
      // The contacts struck at the flight's ends first (the one-contact checks), then the others.
      const bool at_start = c == from, at_end = c == to;
      const ModalContact& mc = b.contacts[c];
      const std::vector<double>* reuse = mc.parallel >= 0 ? &critical[mc.parallel] : nullptr;
      SegmentCheck seg = CheckSignal(ContactSignal(b, mc, y), mc.gap, duration, reuse, critical[c]);
      if (reuse != nullptr) seg.complete = complete[mc.parallel];
      complete[c] = seg.complete;
      const double xtol = options.rel_tol * std::max(mc.gap, seg.position_scale);
      const double vtol = options.rel_tol * seg.velocity_scale;
      if (in_sequence[c]) {
        if (seg.max_excess > orbit.max_excess) orbit.max_excess = seg.max_excess;
      } else {
        // Its gap over the whole flight: interior maxima and both ends.
        double excess = seg.max_excess, at = start + seg.t_at_max;
        Eigen::VectorXd y_end = y;
        Flow(b, duration, y_end);
        for (const auto& [value, time] : {std::pair(ContactPosition(b, mc, y) - mc.gap, start),
                                          std::pair(ContactPosition(b, mc, y_end) - mc.gap, end)}) {
          if (value > excess) {
            excess = value;
            at = time;
          }
        }
        if (excess > orbit.other_excess) {
          orbit.other_excess = excess;
          orbit.other_contact = c;
        }
        if (nc3 && seg.complete && excess > xtol) {
          why << "NC3: contact " << c + 1 << "'s gap closes (by " << excess << ") at t = " << at;
          nc3 = false;
        }
      }
      if (nc3 && !seg.complete) {
        why << "NC3 undetermined: the search for maxima of x_c on the flight from t = " << start
            << " hit its work limit";
        nc3 = false;
      } else if (nc3 && in_sequence[c] && seg.max_excess > xtol) {
        why << "NC3: x_c exceeds d by " << seg.max_excess << " at t = " << start + seg.t_at_max;
        if (contacts > 1) why << " (contact " << c + 1 << ")";
        nc3 = false;
      } else if (nc3 && at_start && seg.start_velocity > vtol) {
        why << "NC3: v_c = " << seg.start_velocity << " > 0 just after the impact at t = " << start;
        nc3 = false;
      } else if (nc3 && at_end && seg.end_velocity < -vtol) {
        why << "NC3: v_c = " << seg.end_velocity << " < 0 just before the impact at t = " << end;
        nc3 = false;
      } else if (nc3 && in_sequence[c] && !at_start && !at_end) {
        // A contact of the sequence not struck at this flight's ends: its gap stays open there too.
        Eigen::VectorXd y_end = y;
        Flow(b, duration, y_end);
        const double e0 = ContactPosition(b, mc, y) - mc.gap, e1 = ContactPosition(b, mc, y_end) - mc.gap;
        if (std::max(e0, e1) > xtol) {
          why << "NC3: contact " << c + 1 << "'s gap closes at t = " << (e0 > e1 ? start : end);
          nc3 = false;
        }
      } else if (nc3 && at_start != at_end) {
        // Struck at one end only: the other end must be clear of its wall.
        Eigen::VectorXd y_end = y;
        if (at_start) Flow(b, duration, y_end);
        const double value = ContactPosition(b, mc, at_start ? y_end : y) - mc.gap;
        if (value > xtol) {
          why << "NC3: contact " << c + 1 << "'s gap closes at t = " << (at_start ? end : start);
          nc3 = false;
        }
      }
    }
    Flow(b, duration, y);
    const ModalContact& struck = b.contacts[to];
    if (k + 1 < orbit.impacts) nc2 = std::max(nc2, std::abs(ContactPosition(b, struck, y) - struck.gap) / struck.gap);
    Impact(b, struck, AnalysisBasis::kRestitution, y);
    start = end;
  }
  orbit.nc2_residual = nc2;
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
