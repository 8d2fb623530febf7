#pragma once
// GSL without its error handler. GSL reports a bad bracket, a non-enclosed
// minimum or a non-finite function value through a process-wide handler that
// aborts by default. That handler is the application's choice: the library
// never changes it. Instead every GSL call here is made so that it cannot
// raise: brackets and enclosures are checked before the call, and function
// values pass through FiniteFunction, which hands GSL a finite stand-in for a
// non-finite value and records that it did, for the caller to act on.
#include <gsl/gsl_math.h>

#include <cmath>
#include <functional>

namespace nsmodal::internal {

class FiniteFunction {
 public:
  // stand_in: what GSL sees instead of a non-finite value (0 ends a root
  // search at once; a huge value keeps a minimiser away).
  FiniteFunction(std::function<double(double)> f, double stand_in) : f_(std::move(f)), stand_in_(stand_in) {}
  gsl_function Gsl() { return gsl_function{&Call, this}; }
  bool saw_non_finite() const { return non_finite_; }

 private:
  static double Call(double x, void* self) {
    auto* me = static_cast<FiniteFunction*>(self);
    const double v = me->f_(x);
    if (std::isfinite(v)) return v;
    me->non_finite_ = true;
    return me->stand_in_;
  }
  std::function<double(double)> f_;
  double stand_in_;
  bool non_finite_ = false;
};

}  // namespace nsmodal::internal
