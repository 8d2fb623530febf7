// libFuzzer target: the scene parser, and what a parsed scene reaches at once
// (the modal basis, the analysis basis, the orbits at one period; for a damped
// or forced scene the closed-form flight, a short exact simulation and the
// forced periodic orbits at the scene's frequency; with a rigid-body mode, a
// short exact simulation). Any input
// must end in a scene or an InputError naming a field: never a crash, a hang
// (libFuzzer's -timeout), memory exhaustion (-rss_limit_mb) or a potential
// orbit with a non-finite energy, state or multiplier (trapped here).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "nsmodal/atlas.h"
#include "nsmodal/error.h"
#include "nsmodal/forced_orbit.h"
#include "nsmodal/scene.h"
#include "nsmodal/simulate.h"
#include "nsmodal/simulate_settings.h"
#include "nsmodal/truncation.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const nsmodal::Scene scene = nsmodal::ParseScene(text, "<fuzz>");
    // A bar of up to 2,000 elements takes one line: beyond 64 dofs the
    // eigen-decompositions alone pass libFuzzer's time limit under the
    // sanitizers. Large systems are the tests' and benchmarks' (bar_test,
    // stability_test, bench_analytic); the parse itself is fuzzed whole.
    if (scene.model.dofs() > 64) return 0;
    // A modal truncation the scene asks for (simulate.modes, a whole number
    // as the CLI demands): the reduced model passed Validate inside, and its
    // maps and bound are finite.
    // The [simulate] table resolved as the commands resolve it (settings.h).
    const auto request = nsmodal::SimulateSettings().Resolve({&scene.simulate});
    if (const std::optional<long> k = request.options.modes; k && std::abs(*k) <= 64) {
      const nsmodal::ModalTruncation t = nsmodal::TruncateModes(scene.model, static_cast<int>(*k), "simulate.modes");
      if (!t.to_physical.allFinite() || !t.from_physical.allFinite() || !(t.residual_flexibility >= 0.0) ||
          !std::isfinite(t.ContactBound(1.0))) {
        __builtin_trap();
      }
    }
    if (!scene.model.Conservative()) {
      const nsmodal::Model& m = scene.model;
      const Eigen::VectorXd periods = nsmodal::MakeModalBasis(m).Periods();
      const double longest = periods.maxCoeff();
      nsmodal::SimulateOptions sim;
      sim.t_end = 3.0 * longest;
      sim.sample_dt = 0.0;
      // A bound on the work of one input (~0.5 s under the sanitizers): a
      // run that needs more ends with status step_limit, which is checked.
      sim.max_steps = 20000;
      const Eigen::VectorXd rest = Eigen::VectorXd::Zero(m.dofs());
      const nsmodal::SimulationSummary s = nsmodal::Simulate(m, rest, rest, sim);
      if (s.status == nsmodal::SimulationStatus::kFinished && !s.final_state.allFinite()) __builtin_trap();
      if (s.status == nsmodal::SimulationStatus::kSolverError && s.message.empty()) __builtin_trap();

      // The forced orbits' work grows as the forcing period counted in the
      // flow's fastest time scales (ForcedProblem::fastest_rate: the energy
      // quadrature and the NC3 searches resolve it over the period; 5.8 s in a
      // release build for 15,000 of them, an input this fuzzer found; the
      // library refuses beyond 1e5). Beyond 1e3 the input stops here: a bound
      // on the work per input. (Counted in undamped periods, an overdamped
      // mode, decaying at up to 2 zeta w_k, or a heavy slow mode let more in.)
      const bool forced = m.forcing.HasHarmonic() && m.NumContacts() == 1 && (m.HasDamping() || !m.AllRestitution(1.0));
      if (forced) {
        const nsmodal::ForcedProblem p(m, 1, 1, m.forcing.frequency, m.forcing.amplitude.cwiseAbs().maxCoeff());
        if (p.period() * p.fastest_rate() > 2.0 * M_PI * 1e3) return 0;
        for (const Eigen::VectorXd& u : p.FindAll()) {
          const nsmodal::ForcedOrbit o = p.Orbit(u);
          if (!std::isfinite(o.energy) || !o.after.front().allFinite()) __builtin_trap();
        }
      }
      return 0;
    }
    const nsmodal::ModalBasis modal = nsmodal::MakeModalBasis(scene.model);
    if (modal.rigid > 0) {
      // Rigid-body modes: the analysis refuses them; the exact integrator
      // flies the drift. The contact dof pushed at the obstacle, for three
      // of the slowest elastic periods, bounded in steps as above (along
      // contact 1's normal, towards its wall).
      const int n = scene.model.dofs();
      nsmodal::SimulateOptions sim;
      sim.t_end = 3.0 * modal.Periods().tail(n - modal.rigid).maxCoeff();
      sim.sample_dt = 0.0;
      sim.max_steps = 20000;
      const Eigen::VectorXd v0 = scene.model.FirstContact().normal.normalized();
      const nsmodal::SimulationSummary s = nsmodal::Simulate(scene.model, Eigen::VectorXd::Zero(n), v0, sim);
      if (s.status == nsmodal::SimulationStatus::kFinished && !s.final_state.allFinite()) __builtin_trap();
      if (s.status == nsmodal::SimulationStatus::kSolverError && s.message.empty()) __builtin_trap();
      return 0;
    }
    const nsmodal::AnalysisBasis b(scene.model);
    nsmodal::SweepOptions opt;
    opt.threads = 1;
    for (int impacts : {1, 2}) {
      for (const nsmodal::OrbitRecord& r : nsmodal::OrbitsAt(b, 1.37 * b.Periods().minCoeff(), impacts, opt)) {
        // A potential orbit is a result: never a silent inf or NaN in it.
        if (r.orbit.potential && (!std::isfinite(r.orbit.energy) || !r.orbit.z0.allFinite())) __builtin_trap();
        if (r.stability && !std::isfinite(r.stability->max_modulus)) __builtin_trap();
      }
    }
  } catch (const nsmodal::InputError&) {
  }
  return 0;
}
