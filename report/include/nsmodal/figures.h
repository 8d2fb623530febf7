#pragma once
// The paper's Figs. 2-15 redrawn from an atlas. Each figure is
// DIR/figNN_name.{csv,png,svg} (+ the gnuplot scripts), the CSV holding
// exactly what is drawn; trajectory CSVs hold one orbit per block, blocks
// separated by a blank line (gnuplot's convention for separate curves). The
// subjects are chosen from the atlas (figure_subjects.h), so another system
// gets its corresponding figures; a figure whose subject does not exist is
// skipped with a line in `log`.
#include <ostream>

#include "nsmodal/atlas.h"
#include "nsmodal/output.h"

namespace nsmodal::report {

struct FiguresResult {
  int drawn = 0, failed = 0;  // charts drawn, charts gnuplot could not draw
};

// contact: 0-based index of the contact dof. Throws OutputError when a data
// file cannot be written.
FiguresResult DrawPaperFigures(const AnalysisBasis& b, int contact, const Atlas& atlas, const OutputDir& dir,
                               std::ostream& log);

}  // namespace nsmodal::report
