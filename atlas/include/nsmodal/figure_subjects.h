#pragma once
// Which orbits each of the paper's figures shows, chosen from an atlas, so
// that another system gets its corresponding figures (report/figures.h draws
// them). Each choice returns nothing, or says why not, when its subject does
// not exist on the grid.
#include <optional>
#include <string>
#include <vector>

#include "nsmodal/atlas.h"
#include "nsmodal/explore.h"

namespace nsmodal {

// The grid of the figures' sweeps (figures --period): `text`, FROM:TO:STEP,
// or by default T from 0.01 to 4 T_max (rounded up) by 0.01; at least two
// periods, within the range and the work limit of both sweeps and the
// transitions (CheckSweepWork). Throws InputError naming `field`.
PeriodGrid FiguresGrid(const AnalysisBasis& b, const std::optional<std::string>& text,
                       const std::string& field = "period");

// t = T/2 to round-off of the roots (~1e-15 relative): the 2-ipp root that is
// always there (eq. 26), or a graze at half the period.
bool AtHalfPeriod(double t, double period);
bool IsHalfPeriodRoot(const Orbit& o);
bool IsGrazing(const Bridge& br);
bool GrazesAtHalfPeriod(const Bridge& br);

// The linear mode i grazing d at t = 0 (x_c = d cos(w_i t)): the limit of the
// 1-ipp family at a modal transition T = k T_i (eq. 24), as a 1-ipp orbit.
Orbit GrazingMode(const AnalysisBasis& b, int mode, double period);
// The mode whose multiple is the modal period T (T = k T_i).
int ModeOf(const AnalysisBasis& b, double period);

// Fig. 2 as the paper draws it: a motion from ker A_2 (NC1) that fails NC2
// and NC3. At the root (t2, T) of a potential 2-ipp orbit the kernel has
// dimension 2 (eq. 28); its element with x_c(0) = d and x_c(t2) = `at_t2`
// flips v_c at t2 away from the obstacle. Returned evaluated (EvaluateOrbit:
// nc2_residual = |at_t2 - d| / d, max_excess the NC3 excess), or nullopt when
// the two conditions do not fix one element (a bridge) or it exceeds d
// nowhere. `at_t2` must not be d.
std::optional<Orbit> KernelMotionOffTheObstacle(const AnalysisBasis& b, const Orbit& potential, double at_t2);
// The subject of Fig. 2: the kernel motion with x_c(t2) = d / 2 at the first
// potential 2-ipp root off T/2 of the sweep where it exceeds d by 5 % to
// 100 % of d (visible, not absurd); nullopt when there is none.
std::optional<Orbit> NotAdmissibleExample(const AnalysisBasis& b, const Atlas& atlas);

// Figs. 4 and 10: a modal transition T = k T_i that bounds an admissible zone,
// and the side of it where the 1-ipp orbits are admissible (+1 right, -1 left,
// 0: none found). The first with T > 1.5 T_i is preferred, as in the paper
// (2 T_1): next to k = 1 the zone often runs into a singular transition.
struct ModalPick {
  double period = 0.0;
  int side = 0;
  double width = 0.0;  // distance to the next transition on that side
};
ModalPick PickModalTransition(const AnalysisBasis& b, const Atlas& atlas);

// Figs. 5 and 13-15: the grazing bridge of the paper's kind (the graze at half
// the period) first, else the first grazing one; null when there is none.
const Bridge* PaperBridge(const Atlas& atlas);

// Fig. 9: a grazing 1-ipp orbit whose two grazes (t_g, T - t_g) make it an
// admissible 3-ipp orbit too.
struct TwoGrazes {
  const Bridge* bridge = nullptr;
  Orbit one, three;
};
std::optional<TwoGrazes> TwoGrazesExample(const AnalysisBasis& b, const Atlas& atlas);

// Figs. 11-12: the 2-ipp nonsmooth mode through the grazing linear mode of the
// shortest period T_i, taken at T = 3 T_i with t2 = T_i (a root: the mode
// grazes d at 0, T_i and 2 T_i) and followed by continuation within
// [T / 2, 3 T / 2]; `run` indexes the admissible stretch of the branch next
// to the mode (the longer side). Empty run: `why_not` says why.
struct ModeBranch {
  int mode = 0;
  double period = 0.0, t2 = 0.0;
  std::vector<BranchPoint> branch;
  std::vector<std::size_t> run;
  std::string why_not;
};
ModeBranch TwoImpactModeBranch(const AnalysisBasis& b);

// Fig. 16 (beyond the paper): an admissible 3-ipp family that is not a
// lower-m orbit. The exploratory search (explore.h, default grid) at
// T = 1, 2, ... up to the atlas's last period (at most 100 periods, evenly
// spread), each admissible new orbit followed by FollowOddImpactFamily with
// the atlas's step over [T / 2, 2 T] within the atlas; a family whose
// admissible stretch ends on a 1-ipp grazing transition first (where it meets
// the 1-ipp family), then the longest stretch. Empty `family`: `why_not` says why.
struct ThreeImpactPick {
  Orbit start;
  std::vector<Orbit> family;        // ascending T, start included
  double admissible_from = 0.0, admissible_to = 0.0;  // ends of start's admissible stretch
  std::string why_not;
};
ThreeImpactPick ThreeImpactFamilyExample(const AnalysisBasis& b, const Atlas& atlas);

}  // namespace nsmodal
