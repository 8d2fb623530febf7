#pragma once
// The paper's Figs. 1-15 redrawn from an atlas, the figures beyond it
// (16-18) and the pictures the dynamics needs (the multipliers along the
// 1-impact branch, a time history, the validation, the frequency-energy plot
// of every family; a bar's contact in space and time). Each figure is
// DIR/NAME.{csv,png,svg,pdf,column.pdf} (+ the gnuplot scripts), the CSV holding
// exactly what is drawn; trajectory CSVs hold one orbit per block, blocks
// separated by a blank line (gnuplot's convention for separate curves). The
// subjects are chosen from the atlas (figure_subjects.h), so another system
// gets its corresponding figures; a figure whose subject does not exist is
// skipped with a line in `log`.
#include <ostream>

#include "nsmodal/atlas.h"
#include "nsmodal/output.h"
#include "nsmodal/tables.h"
#include "nsmodal/work_precision.h"

namespace nsmodal::report {

struct FiguresResult {
  int drawn = 0, failed = 0;  // charts drawn, charts gnuplot could not draw
};

// contact: 0-based index of the contact dof; `model`: the system (drawn,
// and simulated by the time history and the validation). Writes to `log` a
// line per figure and the count drawn. Throws OutputError when a data file
// cannot be written.
FiguresResult DrawPaperFigures(const Model& model, const AnalysisBasis& b, int contact, const Atlas& atlas,
                               const OutputDir& dir, std::ostream& log);

// bar_spacetime: the bar's contact in space and time (the model of a scene's
// [system] bar): the displacement u(x, t) / d along the bar over three
// periods T_1 of a motion started in the first mode's velocity, the impacts
// at the contact marked; below, the contact end's u / d.
FiguresResult DrawBarFigures(const Model& model, const BarSpec& bar, const OutputDir& dir, std::ostream& log);

// Fig. 18 alone (the frequency-energy plot of the impact sequences) over
// `periods`: for a model with a rigid-body mode, which has no 1-impact
// families for the paper's Figs. 2-17 to follow.
FiguresResult DrawSequenceFigures(const AnalysisBasis& b, const std::vector<double>& periods, const OutputDir& dir,
                                  std::ostream& log);

// One log-log chart of error against CPU time per work-precision case, a line
// per integrator, DIR/work_precision_CASE.{png,svg}, drawn from
// DIR/work_precision.csv (written before). Returns the number of charts gnuplot
// could not draw, each named in `log`.
int DrawWorkPrecisionCharts(const OutputDir& dir, const std::vector<WorkPrecisionRow>& rows, std::ostream& log);

// The response charts from DIR/response.csv, DIR/response_points.csv (the
// `points`) and (if `backbone`, its records) DIR/backbone.csv, written before:
// DIR/response_energy (mean energy) and DIR/response_amplitude (the impact
// velocity) against w (or the forcing amplitude when `frequency` is false).
// One colour per level of the held parameter (the level map of style.toml,
// dark for the lowest); admissible and stable: solid; admissible and
// unstable: dashed; not admissible: grey dotted; the backbone black (dotted
// where unstable); the special points of the admissible parts as symbols.
// Returns the number of charts not drawn, each named in `log`.
int DrawResponseCharts(const OutputDir& dir, const std::vector<ResponseRow>& rows,
                       const std::vector<SpecialPoint>& points, int dofs, const std::vector<OrbitRecord>* backbone,
                       bool frequency, int periods, std::ostream& log);

// The curve chart of `continue --second` from DIR/curve.csv, written before:
// DIR/curve, the second parameter against the first, each curve a line in
// its kind's style, the points where it meets another kind's curve (and a
// fold curve's cusps) as symbols; with `backbone` (the first parameter the
// frequency), the conservative twin's 1-impact transitions as vertical lines
// at w = n 2 pi / T. Returns 1 when the chart was not drawn (named in `log`).
int DrawCurveChart(const OutputDir& dir, const std::vector<CurvePoint>& rows, int dofs, const std::string& followed,
                   const std::string& first, const std::string& second, const std::vector<Transition>* backbone,
                   int periods, std::ostream& log);

}  // namespace nsmodal::report
