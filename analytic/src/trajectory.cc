#include "nsmodal/trajectory.h"

#include <vector>

#include "nsmodal/flow.h"
#include "nsmodal/check.h"

namespace nsmodal {

Eigen::MatrixXd OrbitTrajectory(const AnalysisBasis& b, const Orbit& orbit, int samples) {
  NSMODAL_CHECK(samples >= 2);
  const int n = b.n;
  std::vector<double> ends = orbit.times;
  ends.push_back(orbit.period);
  const long flights = static_cast<long>(ends.size());
  Eigen::MatrixXd out(flights * (samples + 1), 1 + 2 * n);
  Eigen::VectorXd y = orbit.y0;
  double start = 0.0;
  long row = 0;
  for (long k = 0; k < flights; ++k) {
    const double duration = ends[k] - start;
    for (int j = 0; j <= samples; ++j) {
      Eigen::VectorXd yj = y;
      // The last sample at the impact itself: duration * samples / samples
      // can be an ulp off, and the impact's two rows must share their time.
      const double t = j == samples ? duration : duration * j / samples;
      Flow(b, t, yj);
      out(row, 0) = start + t;
      out.row(row).tail(2 * n) = PhysicalOf(b, yj).transpose();
      ++row;
    }
    Flow(b, duration, y);
    ElasticImpact(b, y);
    start = ends[k];
  }
  return out;
}

Eigen::MatrixXd ShiftTrajectory(const Eigen::MatrixXd& trajectory, double shift, double period) {
  // The rows from `shift` on come first (moved back by shift), then the
  // others (moved on by T - shift): the same closed curve read from another
  // start. Rows exactly at `shift`: an impact there (two rows, before and
  // after) is split, the row after it starts the curve and the row before it
  // ends it at T; a single row both starts and ends it, so the curve closes.
  const long rows = trajectory.rows();
  long first = 0;  // first row with t >= shift
  while (first < rows && trajectory(first, 0) < shift) ++first;
  long at = 0;     // rows exactly at shift
  while (first + at < rows && trajectory(first + at, 0) == shift) ++at;
  std::vector<long> order;
  std::vector<double> times;
  const long start = at == 2 ? first + 1 : first;
  for (long i = start; i < rows; ++i) {
    order.push_back(i);
    times.push_back(trajectory(i, 0) - shift);
  }
  for (long i = 0; i < first; ++i) {
    order.push_back(i);
    times.push_back(trajectory(i, 0) - shift + period);
  }
  if (at >= 1) {
    order.push_back(first);
    times.push_back(period);
  }
  Eigen::MatrixXd out(static_cast<long>(order.size()), trajectory.cols());
  for (std::size_t r = 0; r < order.size(); ++r) {
    out.row(static_cast<long>(r)) = trajectory.row(order[r]);
    out(static_cast<long>(r), 0) = times[r];
  }
  return out;
}

}  // namespace nsmodal
