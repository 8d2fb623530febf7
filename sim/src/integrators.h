#pragma once
// The three integrators behind Simulate() (simulate.h). Internal.
#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <vector>

#include "nsmodal/contact.h"
#include "nsmodal/simulate.h"

namespace nsmodal::internal {

// The Zeno truncation time: opt.zeno_flight of the shortest linear period
// (simulate.h), one value for the loop and the integrators.
inline double ZenoFlightTime(const ContactModel& cm, const SimulateOptions& opt) {
  return opt.zeno_flight * 2.0 * M_PI / cm.basis.omega.maxCoeff();
}

// Emits trajectory samples at k * sample_dt in (from, to], one call each.
class Sampler {
 public:
  Sampler(const SimulateOptions& options, const SimulationObserver& observer)
      : dt_(options.sample_dt),
        t_start_(options.t_start),
        t_end_(options.t_end),
        times_(options.sample_times),
        observer_(observer) {}
  bool active() const { return (dt_ > 0.0 || !times_.empty()) && static_cast<bool>(observer_.on_sample); }
  // The next sample time: on the sample_dt grid, or the next of sample_times
  // (infinity past the last).
  double NextTime() const {
    if (times_.empty()) return t_start_ + next_ * dt_;
    return next_ < static_cast<long>(times_.size()) ? times_[next_] : std::numeric_limits<double>::infinity();
  }
  // state_at(t) gives the physical state at a sample time t in (from, to].
  template <typename F>
  void Emit(double to, F&& state_at) {
    if (!active()) return;
    while (true) {
      const double t = NextTime();
      if (t > to * (1.0 + 1e-15) || t > t_end_ * (1.0 + 1e-15)) return;
      observer_.on_sample(t, state_at(t));
      ++next_;
    }
  }

 private:
  double dt_, t_start_, t_end_;
  const std::vector<double>& times_;
  const SimulationObserver& observer_;
  long next_ = 0;
};

// The integrators' advances (event_loop.h's Stepper), each defined and
// instantiated in its own file: exact.cc (its two flights), cvode.cc,
// moreau_jean.cc.
struct ConservativeFlight;
struct ForcedFlight;
template <typename Flight>
class ExactStepper;
class CvodeStepper;
class MoreauJeanStepper;

// Builds the Stepper from (cm, x0, v0, options) and runs the event loop.
template <typename Stepper>
SimulationSummary RunIntegrator(const ContactModel& cm, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0,
                                const SimulateOptions& options, const SimulationObserver& observer);
// RunIntegrator's signature for one Stepper, written once: each stepper's file
// instantiates it (template NSMODAL_RUN_INTEGRATOR(S);), every other file
// is told so (extern template ...), so none compiles the loop again.
#define NSMODAL_RUN_INTEGRATOR(...)                                                                        \
  SimulationSummary RunIntegrator<__VA_ARGS__>(const ContactModel&, const Eigen::VectorXd&, const Eigen::VectorXd&, \
                                               const SimulateOptions&, const SimulationObserver&)
extern template NSMODAL_RUN_INTEGRATOR(ExactStepper<ConservativeFlight>);
extern template NSMODAL_RUN_INTEGRATOR(ExactStepper<ForcedFlight>);
extern template NSMODAL_RUN_INTEGRATOR(CvodeStepper);
extern template NSMODAL_RUN_INTEGRATOR(MoreauJeanStepper);

}  // namespace nsmodal::internal
