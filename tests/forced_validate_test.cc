// Validation of forced periodic orbits by long simulations (validate.h):
// the same verdicts as for free orbits.
#include <gtest/gtest.h>

#include <cmath>

#include "nsmodal/forced_orbit.h"
#include "nsmodal/scene.h"
#include "nsmodal/validate.h"

namespace nsmodal {
namespace {

// configs/forced.toml: the paper's system, 2 % modal damping, e = 0.8.
Model Forced() { return LoadScene(NSMODAL_SOURCE_DIR "/configs/forced.toml").model; }

// Every (1,1) orbit at a few frequencies where the response has stable,
// unstable and non-admissible orbits (response_test's curve).
std::vector<ForcedOrbit> Orbits(const Model& m) {
  std::vector<ForcedOrbit> out;
  for (double w : {0.46, 0.5, 0.54, 0.6}) {
    const ForcedProblem p(m, 1, 1, w, 0.3);
    for (const Eigen::VectorXd& u : p.FindAll()) out.push_back(p.Orbit(u));
  }
  return out;
}

TEST(ForcedValidation, EveryVerdictAsForFreeOrbits) {
  const Model m = Forced();
  const std::vector<ForcedOrbit> orbits = Orbits(m);
  ValidateOptions opt;
  opt.periods = 300;
  opt.integrators = {Integrator::kExact, Integrator::kCvode};
  const std::vector<ForcedOrbitValidation> results = ValidateForcedOrbits(m, orbits, opt);
  int stable = 0, unstable_rated = 0, broken = 0;
  for (const ForcedOrbitValidation& v : results) {
    EXPECT_TRUE(v.consistent) << "w = " << v.orbit.frequency << " (" << ToString(v.integrator) << "): " << v.reason;
    if (v.integrator != Integrator::kExact) continue;
    if (!v.orbit.admissible) {
      ++broken;
    } else if (v.orbit.stable) {
      ++stable;
      // Exact: round-off, no growth (multipliers < 1): the tolerance
      // exact_periodicity = 1e-9 after 300 periods.
      EXPECT_LT(v.deviation.back(), 1e-9);
    } else if (v.measured_growth > 0.0) {
      ++unstable_rated;
      EXPECT_NEAR(v.measured_growth, std::log(v.orbit.max_multiplier), 0.3 * std::log(v.orbit.max_multiplier));
    }
  }
  // The set covers the three verdicts.
  EXPECT_GE(stable, 1);
  EXPECT_GE(unstable_rated, 1);
  EXPECT_GE(broken, 1);
}

}  // namespace
}  // namespace nsmodal
