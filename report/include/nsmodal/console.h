#pragma once
// The text a person reads on the console: the lines and tables the commands
// print besides their files. Each function writes to `out` (the CLI passes
// std::cout) and leaves its format flags as it found them.
#include <cstddef>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "nsmodal/atlas.h"
#include "nsmodal/explore.h"
#include "nsmodal/response.h"
#include "nsmodal/simulate_settings.h"
#include "nsmodal/truncation.h"
#include "nsmodal/validate.h"
#include "nsmodal/work_precision.h"

namespace nsmodal::report {

// A progress callback (ParallelFor's, a sweep's): a bar on stderr when it
// is a terminal, else a plain line every 10 s once the run has lasted that
// long (a log: short runs stay quiet).
std::function<void(long done, long count)> ProgressBar(const std::string& label);

// "modal truncation: k of N modes kept (up to w_k rad/s; the first neglected
// w_k+1 rad/s); residual flexibility f m/N", no end of line: each command
// goes on with what the bound means for it.
void PrintTruncation(std::ostream& out, const ModalTruncation& t);

// The line of a sweep on the kept modes (orbits --modes): PrintTruncation
// and the bound's column in orbits.csv.
void PrintSweepTruncation(std::ostream& out, const ModalTruncation& t);

// The line of a simulation on the kept modes (simulate --modes or
// --contact-tolerance): PrintTruncation, the bound at the initial energy and
// the kept modes' part of the start; nothing when the plan keeps every dof.
void PrintSimulationTruncation(std::ostream& out, const SimulationPlan& plan, const Contact& contact);

// explore's summary: the grid samples, dim ker A_m, the potential orbits by
// kind, the smallest defect, the paper's conjecture, and a line per new
// orbit; `periods`: how many periods were searched.
void PrintExplore(std::ostream& out, const ExploreReport& report, long periods);

// explore --follow: a line per family (FollowNewFamilies) followed at `step`.
void PrintFamilies(std::ostream& out, const std::vector<FamilySummary>& families, double step);

// response: a line per branch of a curve ("branch k: n points; how it
// ended", numbered on from first_branch, 0-based) and its notes.
void PrintResponseCurve(std::ostream& out, const ResponseCurve& curve, int first_branch);

// response: a line per peak with the nonsmooth mode at its energy
// (MatchBackbone), for an (m, n) response of n = `periods`.
void PrintResponsePeaks(std::ostream& out, const std::vector<SpecialPoint>& points, const BackboneMatch& match,
                        int periods);

// response --validate: a line per inconsistent run.
void PrintInconsistent(std::ostream& out, const ResponseValidation& validation);
// response --validate: how many of the runs of `orbits` points over
// `periods` periods were consistent, and the file written (`path`).
void PrintResponseValidation(std::ostream& out, const ResponseValidation& validation, std::size_t orbits, int periods,
                             const std::string& path);

// orbit: every potential orbit at one period, a block each (admissibility,
// t2, energy, residuals, the NC3 margin, the state after the impact at t = 0,
// the Floquet multipliers), 12 significant digits.
void PrintOrbits(std::ostream& out, const std::vector<OrbitRecord>& orbits, int impacts, double period);

// figures: the atlas' notes, its periods, transitions and bridges, a line per bridge.
void PrintAtlas(std::ostream& out, const Atlas& atlas);

// bench: the two tables a person reads, error and cost per case and
// integrator setting, and the grazing limits (SummarizeGrazing).
void PrintBenchTables(std::ostream& out, const std::vector<WorkPrecisionRow>& rows,
                      const std::vector<GrazingRow>& grazing);

}  // namespace nsmodal::report
