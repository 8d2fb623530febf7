#include "nsmodal/style.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <toml++/toml.h>

#include "nsmodal/check.h"

namespace nsmodal::report::style {
extern const char* const kStyleToml;  // style_data.cc, generated from report/style.toml

namespace {

struct Series {
  std::string kind, colour, means;
  double width = 1.0, size = 1.0;
  int dash = 1, point = -1;
};

struct Declaration {
  toml::table table;
  std::map<std::string, std::string, std::less<>> colours;
  std::map<std::string, Series, std::less<>> series;
  std::vector<Format> formats;
  std::string dash_patterns;  // "set dashtype N (on, off, ...)" of each dash beyond gnuplot's five
};

// Aborts naming what is wrong: style.toml is the project's, built in.
[[noreturn]] void Broken(const std::string& what) {
  std::fprintf(stderr, "nsmodal: report/style.toml: %s\n", what.c_str());
  NSMODAL_CHECK(!"report/style.toml is consistent");
  std::abort();
}

const toml::table& Table(const toml::table& t, std::string_view key) {
  const toml::table* sub = t[key].as_table();
  if (!sub) Broken("no table [" + std::string(key) + "]");
  return *sub;
}
template <typename T>
T Value(const toml::table& t, std::string_view key, const std::string& where) {
  const std::optional<T> v = t[key].value<T>();
  if (!v) Broken(where + "." + std::string(key) + " is missing or of the wrong type");
  return *v;
}

std::string Number(double x) {
  std::ostringstream os;
  os << x;
  return os.str();
}

Declaration Parse() {
  Declaration d;
  try {
    d.table = toml::parse(kStyleToml);
  } catch (const toml::parse_error& e) {
    Broken(std::string(e.description()));
  }
  for (const auto& [name, v] : Table(d.table, "colours")) {
    const std::optional<std::string> c = v.value<std::string>();
    if (!c || c->empty() || c->front() != '#' || (c->size() != 7 && c->size() != 9)) {
      Broken("colours." + std::string(name.str()) + " is not #RRGGBB or #AARRGGBB");
    }
    d.colours.emplace(std::string(name.str()), *c);
  }
  const toml::table &dashes = Table(d.table, "dashes"), &markers = Table(d.table, "markers");
  // A dash of its own pattern (gnuplot's own five have none): declared in
  // every chart's set-up under its number.
  for (const auto& [name, v] : dashes) {
    const std::string where = "dashes." + std::string(name.str());
    const toml::table* t = v.as_table();
    if (!t) Broken(where + " is not a table");
    const std::optional<std::string> pattern = (*t)["pattern"].value<std::string>();
    if (pattern) d.dash_patterns += "set dashtype " + std::to_string(Value<int>(*t, "gnuplot", where)) + " " + *pattern + "\n";
  }
  for (const auto& [name, v] : Table(d.table, "series")) {
    const std::string where = "series." + std::string(name.str());
    const toml::table* t = v.as_table();
    if (!t) Broken(where + " is not a table");
    Series s;
    s.kind = Value<std::string>(*t, "kind", where);
    const std::string colour = Value<std::string>(*t, "colour", where);
    const auto c = d.colours.find(colour);
    if (c == d.colours.end()) Broken(where + ".colour '" + colour + "' is not in [colours]");
    s.colour = c->second;
    s.width = Value<double>(*t, "width", where);
    s.size = Value<double>(*t, "size", where);
    s.means = Value<std::string>(*t, "means", where);
    const std::string dash = Value<std::string>(*t, "dash", where), marker = Value<std::string>(*t, "marker", where);
    if (!dashes[dash].is_table()) Broken(where + ".dash '" + dash + "' is not in [dashes]");
    if (!markers[marker].is_table()) Broken(where + ".marker '" + marker + "' is not in [markers]");
    s.dash = Value<int>(*dashes[dash].as_table(), "gnuplot", "dashes." + dash);
    s.point = Value<int>(*markers[marker].as_table(), "gnuplot", "markers." + marker);
    d.series.emplace(std::string(name.str()), s);
  }
  for (const char* ext : {"png", "svg", "pdf", "column.pdf"}) {
    const std::string where = std::string("formats.") + ext;
    const toml::table& f = Table(Table(d.table, "formats"), ext);
    const std::string terminal = Value<std::string>(f, "terminal", where);
    const double points = Value<double>(f, "points", where);
    Format format;
    format.extension = ext;
    format.terminal = terminal;
    // size = "W,H" or "Wcm,Hcm"
    const std::string size = Value<std::string>(f, "size", where);
    const std::size_t comma = size.find(',');
    std::size_t used = 0;
    try {
      format.width = std::stod(size.substr(0, comma), &used);
      format.unit = size.substr(used, comma - used);
      format.height = std::stod(size.substr(comma + 1));
    } catch (const std::exception&) {
      Broken(where + ".size '" + size + "' is not W,H or Wcm,Hcm");
    }
    if (comma == std::string::npos || !(format.width > 0 && format.height > 0)) {
      Broken(where + ".size '" + size + "' is not W,H or Wcm,Hcm");
    }
    std::ostringstream os;
    os << " font '," << Value<int>(f, "font", where) << "' linewidth " << Number(Value<double>(f, "lines", where));
    // pdfcairo draws a font size of F as 4/3 F points times its fontscale,
    // 0.5 unless told (measured: font ',7' gave a 4.67 pt text matrix): 0.75
    // prints `font` at its size in points.
    if (terminal == "pdfcairo") os << " fontscale 0.75";
    // (gnuplot's svg terminal has no pointscale: its markers are the PNG's.)
    if (terminal.rfind("svg", 0) == 0) {
      if (points != 1.0) Broken(where + ".points must be 1: gnuplot's svg terminal cannot scale markers");
    } else {
      os << " pointscale " << Number(points);
    }
    format.options = os.str();
    format.key = Value<std::string>(f, "key", where);
    format.key_band = Value<double>(f, "key_band", where);
    if (!(format.key_band > 0.0 && format.key_band <= 1.0)) {
      Broken(where + ".key_band " + Number(format.key_band) + " is not in (0, 1]");
    }
    d.formats.push_back(format);
  }
  return d;
}

const Declaration& The() {
  static const Declaration d = Parse();
  return d;
}

const Series& Role(std::string_view role) {
  const auto it = The().series.find(role);
  if (it == The().series.end()) Broken("no series role '" + std::string(role) + "'");
  return it->second;
}

}  // namespace

const std::vector<Format>& Formats() { return The().formats; }

std::string Format::Terminal(double aspect) const {
  std::ostringstream os;
  const double h = aspect > 0.0 ? aspect * width : height;
  os << terminal << " size " << Number(width) << unit << "," << (unit.empty() ? std::round(h) : h) << unit << options;
  return os.str();
}

std::string Colour(std::string_view name) {
  const auto it = The().colours.find(name);
  if (it == The().colours.end()) Broken("no colour '" + std::string(name) + "'");
  return it->second;
}

std::string RoleColour(std::string_view role) { return Role(role).colour; }

std::string Look(std::string_view role, std::string_view kind, std::string_view colour) {
  Series s = Role(role);
  if (!colour.empty()) s.colour = std::string(colour);
  const std::string k = kind.empty() ? s.kind : std::string(kind);
  std::ostringstream os;
  const std::string lc = "lc rgb '" + s.colour + "'";
  if (k == "lines" || k == "vectors") {
    os << (k == "vectors" ? "nohead " : "") << "lw " << Number(s.width) << " dt " << s.dash << " " << lc;
  } else if (k == "points") {
    os << "pt " << s.point << " ps " << Number(s.size) << " lw " << Number(s.width) << " " << lc;
  } else if (k == "linespoints") {
    os << "lw " << Number(s.width) << " dt " << s.dash << " pt " << s.point << " ps " << Number(s.size) << " " << lc;
  } else if (k == "fill") {
    os << "fs solid 1 noborder fc rgb '" << s.colour << "'";
  } else {
    Broken("series." + std::string(role) + ": no way to draw kind '" + k + "'");
  }
  return os.str();
}

std::string With(std::string_view role, std::string_view kind, std::string_view colour) {
  const std::string k = kind.empty() ? Role(role).kind : std::string(kind);
  return "with " + (k == "fill" ? std::string("filledcurves") : k) + " " + Look(role, k, colour);
}

namespace {
// A role's "with ..." clause up to its colour (for a palette's instead).
std::string Uncoloured(std::string_view role, std::string_view kind = "") {
  std::string with = With(role, kind);
  const std::size_t at = with.rfind("lc rgb '");
  NSMODAL_CHECK(at != std::string::npos);
  return with.substr(0, at);
}
}  // namespace

std::string WithMapped(std::string_view role, std::string_view kind, double f) {
  return Uncoloured(role, kind) + "lc palette frac " + Number(std::clamp(f, 0.0, 1.0));
}

std::string WithPalette(std::string_view role) {
  const Series& s = Role(role);
  if (s.kind == "lines") return Uncoloured(role) + "lc palette";
  std::ostringstream os;
  os << "with points pt " << s.point << " ps " << Number(s.size) << " lw " << Number(s.width) << " lc palette";
  return os.str();
}

std::string Means(std::string_view role) { return Role(role).means; }

std::string Palette(std::string_view map, const std::string& label) {
  const toml::table& m = Table(Table(The().table, "maps"), map);
  const toml::array* stops = m["stops"].as_array();
  if (!stops || stops->empty()) Broken("maps." + std::string(map) + ".stops is missing");
  std::ostringstream os;
  os << "set palette defined (";
  bool first = true;
  for (const toml::node& stop : *stops) {
    const toml::array* pair = stop.as_array();
    if (!pair || pair->size() != 2 || !(*pair)[0].is_number() || !(*pair)[1].is_string()) {
      Broken("maps." + std::string(map) + ".stops: each is [position, \"#RRGGBB\"]");
    }
    os << (first ? "" : ", ") << Number((*pair)[0].value<double>().value()) << " '"
       << (*pair)[1].value<std::string>().value() << "'";
    first = false;
  }
  // (offset 1: gnuplot puts a rotated bar label on its tick labels.)
  os << ")\nset cblabel '" << label << "' offset 1, 0\n";
  return os.str();
}

std::string MapColour(std::string_view map, double f) {
  const toml::array* stops = Table(Table(The().table, "maps"), map)["stops"].as_array();
  if (!stops || stops->empty()) Broken("maps." + std::string(map) + ".stops is missing");
  // The stop nearest to f: a category takes one of the declared colours.
  std::size_t best = 0;
  double gap = INFINITY;
  for (std::size_t k = 0; k < stops->size(); ++k) {
    const double at = (*stops)[k].as_array()->get(0)->value<double>().value_or(0.0);
    if (std::abs(at - f) < gap) {
      gap = std::abs(at - f);
      best = k;
    }
  }
  return (*stops)[best].as_array()->get(1)->value<std::string>().value_or("");
}

std::string CycleColour(std::string_view cycle, std::size_t k) {
  const toml::array* names = Table(The().table, "cycles")[cycle].as_array();
  if (!names || names->empty()) Broken("cycles." + std::string(cycle) + " is missing");
  return Colour((*names)[k % names->size()].value<std::string>().value_or(""));
}

std::string ChartSetup(const Format& format) {
  // (Arrow style 1: the bridge's line with a flat cap at each end, for
  // `with vectors arrowstyle 1`; a plot command's own `size` took a comma.
  // The cap 0.004 of the canvas each side, narrower than a grazing circle:
  // at 0.007 it hid the circle at a grazing bridge's top; at 0.005 a reader
  // found Fig. 15's circle barely wider than it in the PNG.)
  return The().dash_patterns + "ns_key_band = " + Number(format.key_band) + "\nset grid lt 1 lw 0.5 lc rgb '" +
         Colour("grid") + "'\nset key " + format.key +
         " noautotitle\nset style arrow 1 heads size screen 0.004,90 " + Look("bridge", "lines") + "\n";
}

std::string Json() {
  std::ostringstream os;
  os << toml::json_formatter{The().table};
  return os.str();
}

}  // namespace nsmodal::report::style
