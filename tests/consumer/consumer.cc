// Links every installed nsmodal library: the paper's system, its 1-ipp sweep
// and transitions (atlas), a simulation (sim), one orbit validated (validate),
// its row written as CSV (report). Exits non-zero if a number is off.
#include <cmath>
#include <iostream>
#include <sstream>

#include "nsmodal/atlas.h"
#include "nsmodal/tables.h"
#include "nsmodal/validate.h"

int main() {
  using namespace nsmodal;
  const Model model = PaperModel();
  const AnalysisBasis b(model);
  const Sweep sweep = ComputeSweep(b, PeriodGrid{0.05, 40.0, 0.01}, 1);
  const std::vector<Transition> transitions = SweepTransitions(b, sweep);
  const Eigen::VectorXd x0 = Eigen::Vector2d(0.5, 0.0), v0 = Eigen::Vector2d(0.5, 1.2);
  SimulateOptions so;
  so.t_end = 50.0;
  const SimulationSummary s = Simulate(model, x0, v0, so);
  ValidateOptions vo;
  vo.periods = 20;
  const OrbitValidation v = ValidateOrbit(model, sweep.at[745].front().orbit, Integrator::kExact, vo);  // T = 7.5
  std::ostringstream row;
  report::WriteCsvRow(row, report::ValidationColumns(), v);
  long zone_ends = 0;
  for (const Transition& t : transitions) zone_ends += BoundsAZone(t.kind);
  std::cout << zone_ends << " transitions and " << transitions.size() - zone_ends << " stability changes, "
            << s.impacts << " impacts, T = 7.5 " << (v.consistent ? "consistent" : "inconsistent") << "\n";
  // 12 transitions on (0.05, 40] and 6 multiplier crossings (README), energy
  // kept at e = 1.
  return zone_ends == 12 && transitions.size() == 18 && s.energy_drift < 1e-12 && v.consistent && !row.str().empty()
             ? 0
             : 1;
}
