#pragma once
// Closed-form simulation scenes shared by the simulator tests.
#include <cmath>

#include "nsmodal/model.h"

namespace nsmodal::testing {

// The paper's system with e = 0.5, mass 2 at the wall moving in at v = 0.01,
// mass 1 at rest at 1.5 pushing it (a_2 = 2 (x1 - x2) = 1 > 0). The impacts
// accumulate (Zeno) in 2 v+ / (a (1 - e)) = 0.02, during which a_2 changes by
// ~1e-3 relative; the mass is then held until x1 falls to x2 = d, x1 moving
// as the held system x1'' = -2.85 x1 + 2: release at
//   t = acos((1 - 2/2.85) / (1.5 - 2/2.85)) / sqrt(2.85).
struct ZenoScene {
  Model model;
  double x0[2] = {1.5, 1.0};
  double v0[2] = {0.0, 0.01};
  double accumulation_time = 2.0 * 0.005 / (1.0 * 0.5);
  double release_time = std::acos((1.0 - 2.0 / 2.85) / (1.5 - 2.0 / 2.85)) / std::sqrt(2.85);
  ZenoScene() : model(PaperModel()) { model.FirstContact().restitution = 0.5; }
};

}  // namespace nsmodal::testing
