#pragma once
// The visual language of every chart, read from report/style.toml (embedded
// at build time): colours, dashes, markers, series by role, colour maps with
// their one meaning, and the chart formats. Charts name a role ("one_stable",
// "obstacle", "grazing", ...), never a colour: tests/style_test.cc fails when
// a source file outside report/style.toml holds a colour.
//
// An unknown role, colour or map is a bug in the caller (an internal
// invariant, check.h), not a user's mistake: the names are the project's.
#include <string>
#include <string_view>
#include <vector>

namespace nsmodal::report::style {

// One output format of a chart (style.toml [formats]).
struct Format {
  std::string extension;  // png, svg, pdf, column.pdf
  std::string terminal;   // gnuplot's terminal ("pngcairo", "svg dynamic", ...)
  double width = 0.0, height = 0.0;
  std::string unit;       // of width and height: "" (pixels) or "cm"
  std::string options;    // font, line width, marker scale
  std::string key;        // the key's set-up (samplen, spacing, height, width)
  double key_band = 1.0;  // the scale of a multi-panel chart's key band (gnuplot's ns_key_band)
  // The "set terminal" line; `aspect` > 0: height = aspect * width (a chart
  // whose subject has its own shape, the model's drawing), else the format's.
  std::string Terminal(double aspect = 0.0) const;
};
const std::vector<Format>& Formats();

// "#RRGGBB" (or "#AARRGGBB") of a named colour of [colours].
std::string Colour(std::string_view name);

// The gnuplot clause drawing a series of this role, e.g.
// "with lines lw 2.5 dt 2 lc rgb '<its colour>'" or "with points pt 6 ps 0.5
// lw 1 lc rgb '<its colour>'". `kind` overrides the role's kind ("lines", "points",
// "linespoints"): a family drawn as points in one chart keeps its colour.
// `colour` (a colour of style.toml: Colour, CycleColour) overrides the
// role's, for categories of a cycle drawn with a role's line or marker.
std::string With(std::string_view role, std::string_view kind = "", std::string_view colour = "");
// The same without "with KIND": for an arrow, or a kind's own options first
// ("with filledcurves above y=1 " + Look("excess")).
std::string Look(std::string_view role, std::string_view kind = "", std::string_view colour = "");
// "#RRGGBB" of a role's colour (a series drawn in another role's colour).
std::string RoleColour(std::string_view role);
// Points of the role's marker and size (or, for a role of kind "lines", its
// line) coloured by the palette (the third column of `using`): a family
// whose colour is a map's one meaning.
std::string WithPalette(std::string_view role);
// The role's look at the fraction f of the chart's palette (`lc palette frac
// f`: one colour for the whole layer, drawn as one path, so a dash runs on
// along it; a layer coloured point by point restarts it at each segment).
std::string WithMapped(std::string_view role, std::string_view kind, double f);
// What the role means, for a key or a caption.
std::string Means(std::string_view role);

// "set palette defined (...)\nset cblabel '...'\n" for a colour map of
// [maps]; `label` names what the bar measures on the map's one meaning.
std::string Palette(std::string_view map, const std::string& label);

// The colour of the stop nearest to f in [0, 1] of a colour map of [maps]:
// a few categories in order (forcing levels), each one of the map's stops.
std::string MapColour(std::string_view map, double f);

// The k-th colour of a cycle of [cycles] (repeats past its end).
std::string CycleColour(std::string_view cycle, std::size_t k);

// Gnuplot set-up shared by every chart: the grid's colour, a compact key
// (the format's).
std::string ChartSetup(const Format& format);

// The whole declaration as JSON (for the Python module's nsmodal.style).
std::string Json();

}  // namespace nsmodal::report::style
