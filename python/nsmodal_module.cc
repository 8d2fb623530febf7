// The Python face of nsmodal: the same library calls as the CLI, NumPy arrays
// in and out. Tables come back as dicts of column arrays keyed as the CSV
// columns (report/tables.h declares both); documents (a simulation summary,
// a validation summary, an orbit) as the dicts of their JSON files.
#include <pybind11/complex.h>
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <chrono>
#include <csignal>
#include <cstddef>
#include <deque>
#include <future>
#include <thread>
#include <functional>
#include <stdexcept>
#include <limits>
#include <optional>
#include <string>
#include <tuple>
#include <variant>
#include <vector>

#include "nsmodal/atlas.h"
#include "nsmodal/curve.h"
#include "nsmodal/forced_orbit.h"
#include "nsmodal/settle.h"
#include "nsmodal/family_parameter.h"
#include "nsmodal/style.h"
#include "nsmodal/error.h"
#include "nsmodal/input_checks.h"
#include "nsmodal/json.h"
#include "nsmodal/modal_basis.h"
#include "nsmodal/model.h"
#include "nsmodal/model_spec.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/output.h"
#include "nsmodal/response.h"
#include "nsmodal/scene.h"
#include "nsmodal/simulate.h"
#include "nsmodal/simulate_settings.h"
#include "nsmodal/settings.h"
#include "nsmodal/truncation.h"
#include "nsmodal/stability.h"
#include "nsmodal/stop.h"
#include "nsmodal/tables.h"
#include "nsmodal/two_impact.h"
#include "nsmodal/validate.h"
#include "nsmodal/validate_settings.h"

namespace py = pybind11;
using namespace nsmodal;

namespace {

// Keyword checks that pybind11's own conversions do not make. Python's bool
// is an int (True == 1), so a plain int or float parameter takes gap=True or
// impacts=True; the CLI, which parses text, has no such spelling, and a flag
// set by mistake must not become a count or a length. Real<"gap"> and
// Integer<"impacts"> take the place of double and int in the signatures and
// refuse a bool (TypeError), a non-number (TypeError) and an integer beyond
// an int (ValueError), naming the keyword and the value; the checks of what
// the value may be (thread counts, ranges) are the library's, shared with
// the CLI (input_checks.h, the options' Validate).
template <std::size_t N>
struct ArgName {
  char text[N];
  constexpr ArgName(const char (&s)[N]) { std::copy_n(s, N, text); }  // NOLINT: implicit, for the template argument
};

template <ArgName kName>
struct Real {
  double value = 0.0;
  operator double() const { return value; }  // NOLINT: a double to the code that takes it
};

template <ArgName kName>
struct Integer {
  int value = 0;
  operator int() const { return value; }  // NOLINT: an int to the code that takes it
};

std::string Repr(py::handle h) { return py::repr(h).cast<std::string>(); }

bool IsBool(py::handle h) {
  if (PyBool_Check(h.ptr())) return true;
  const std::string type = Py_TYPE(h.ptr())->tp_name;
  return type == "numpy.bool_" || type == "numpy.bool";
}

double RealOf(py::handle h, const char* name) {
  if (IsBool(h)) throw py::type_error(std::string(name) + ": must be a number, got " + Repr(h) + " (a bool)");
  if (PyFloat_Check(h.ptr()) || PyLong_Check(h.ptr()) || (PyNumber_Check(h.ptr()) && !PyComplex_Check(h.ptr()))) {
    const double v = PyFloat_AsDouble(h.ptr());
    if (!(v == -1.0 && PyErr_Occurred())) return v;
    PyErr_Clear();
  }
  throw py::type_error(std::string(name) + ": must be a number, got " + Repr(h));
}

int IntOf(py::handle h, const char* name) {
  if (IsBool(h)) throw py::type_error(std::string(name) + ": must be an integer, got " + Repr(h) + " (a bool)");
  if (!PyIndex_Check(h.ptr())) throw py::type_error(std::string(name) + ": must be an integer, got " + Repr(h));
  const py::object index = py::reinterpret_steal<py::object>(PyNumber_Index(h.ptr()));
  if (!index) throw py::error_already_set();
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
  if (overflow != 0 || v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max()) {
    throw py::value_error(std::string(name) + ": " + Repr(h) + " is out of range");
  }
  return static_cast<int>(v);
}

// A sequence of numbers (a list, a tuple, a 1-D array) as doubles; a string
// or a scalar is refused naming the argument.
std::vector<double> DoublesOf(py::handle h, const char* name) {
  if (py::isinstance<py::str>(h) || !py::isinstance<py::iterable>(h)) {
    throw py::type_error(std::string(name) + ": must be a sequence of numbers, got " + Repr(h));
  }
  std::vector<double> out;
  for (py::handle item : py::reinterpret_borrow<py::iterable>(h)) out.push_back(RealOf(item, name));
  return out;
}

}  // namespace

namespace pybind11::detail {
template <ArgName kName>
struct type_caster<Real<kName>> {
  PYBIND11_TYPE_CASTER(Real<kName>, const_name("float"));
  bool load(handle src, bool) {
    value.value = RealOf(src, kName.text);
    return true;
  }
  static handle cast(const Real<kName>& r, return_value_policy, handle) { return PyFloat_FromDouble(r.value); }
};
template <ArgName kName>
struct type_caster<Integer<kName>> {
  PYBIND11_TYPE_CASTER(Integer<kName>, const_name("int"));
  bool load(handle src, bool) {
    value.value = IntOf(src, kName.text);
    return true;
  }
  static handle cast(const Integer<kName>& i, return_value_policy, handle) { return PyLong_FromLong(i.value); }
};
}  // namespace pybind11::detail

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A JSON document as Python objects (through the json module: the dict is
// exactly what the command writes to its file).
py::object ToPython(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

// Columns of a table as a dict of arrays: real columns float64 (NaN where
// missing), integer columns int64, boolean columns bool (False where
// missing), text columns lists of str.
//
// NaN in a float column is the missing marker and nothing else: a table
// holds no inf or nan as a value (table.h; every cell passes CellOf's
// check), so NaN here is exactly an empty field of the CSV. It is what a
// pandas user expects: pandas.read_csv reads those empty fields as NaN in a
// float64 column, DataFrame(d).isna() finds them, and the column stays
// numeric (an object column of None would not vectorise, and a separate
// mask column would be a second name for the same fact). Scalars that do not
// apply, in the dicts of the JSON documents, are None.
template <class Row>
py::dict TableDict(const report::Columns<Row>& columns, const std::vector<const Row*>& rows) {
  py::dict out;
  const py::ssize_t n = static_cast<py::ssize_t>(rows.size());
  for (const report::Column<Row>& col : columns) {
    switch (col.kind) {
      case report::ColumnKind::kReal: {
        py::array_t<double> a(n);
        auto w = a.mutable_unchecked<1>();
        for (py::ssize_t i = 0; i < n; ++i) {
          const report::Cell c = report::CellOf(col, *rows[i]);
          w(i) = std::holds_alternative<double>(c) ? std::get<double>(c) : kNaN;
        }
        out[py::str(col.name)] = a;
        break;
      }
      case report::ColumnKind::kInteger: {
        py::array_t<long> a(n);
        auto w = a.mutable_unchecked<1>();
        for (py::ssize_t i = 0; i < n; ++i) w(i) = std::get<long>(report::CellOf(col, *rows[i]));
        out[py::str(col.name)] = a;
        break;
      }
      case report::ColumnKind::kBool: {
        py::array_t<bool> a(n);
        auto w = a.mutable_unchecked<1>();
        for (py::ssize_t i = 0; i < n; ++i) {
          const report::Cell c = report::CellOf(col, *rows[i]);
          w(i) = std::holds_alternative<bool>(c) && std::get<bool>(c);
        }
        out[py::str(col.name)] = a;
        break;
      }
      case report::ColumnKind::kText: {
        py::list l;
        for (py::ssize_t i = 0; i < n; ++i) {
          const report::Cell c = report::CellOf(col, *rows[i]);
          l.append(std::holds_alternative<std::string>(c) ? std::get<std::string>(c) : std::string());
        }
        out[py::str(col.name)] = l;
        break;
      }
    }
  }
  return out;
}

template <class Row>
std::vector<const Row*> Pointers(const std::vector<Row>& rows) {
  std::vector<const Row*> p;
  p.reserve(rows.size());
  for (const Row& r : rows) p.push_back(&r);
  return p;
}

// The orbits table of a sweep: its CSV columns, each a 1-D array, so that
// pandas.DataFrame takes it in one call (stack() gives the state and the
// multipliers as matrices).
py::dict OrbitsDict(const Sweep& sweep, int dofs) {
  std::vector<const OrbitRecord*> rows;
  for (const auto& list : sweep.at) {
    for (const OrbitRecord& r : list) rows.push_back(&r);
  }
  return TableDict(report::OrbitColumns(dofs), rows);
}

// Columns name1, name2, ... of a table as one matrix (rows x N); "mu": the
// complex multipliers from mu1_re, mu1_im, ... (NaN where not computed).
py::array Stack(const py::dict& table, const std::string& name) {
  const bool complex = name == "mu";
  auto key = [&](int k, const char* part) { return name + std::to_string(k) + (complex ? part : ""); };
  int n = 0;
  while (table.contains(py::str(key(n + 1, "_re")))) ++n;
  if (n == 0) throw InputError("name", "the table has no columns " + key(1, "_re") + ", " + key(2, "_re") + ", ...");
  const py::ssize_t rows = py::len(table[py::str(key(1, "_re"))]);
  auto column = [&](const std::string& k) {
    py::array_t<double> a = py::array_t<double>::ensure(table[py::str(k)]);
    if (!a || a.ndim() != 1 || a.shape(0) != rows) throw InputError("table", "column " + k + " is not a 1-D array of the table's length");
    return a;
  };
  if (!complex) {
    py::array_t<double> out({rows, static_cast<py::ssize_t>(n)});
    auto w = out.mutable_unchecked<2>();
    for (int k = 0; k < n; ++k) {
      const py::array_t<double> held = column(key(k + 1, ""));  // alive while read (a converted copy)
      const auto c = held.unchecked<1>();
      for (py::ssize_t i = 0; i < rows; ++i) w(i, k) = c(i);
    }
    return out;
  }
  py::array_t<std::complex<double>> out({rows, static_cast<py::ssize_t>(n)});
  auto w = out.mutable_unchecked<2>();
  for (int k = 0; k < n; ++k) {
    const py::array_t<double> re_held = column(key(k + 1, "_re")), im_held = column(key(k + 1, "_im"));
    const auto re = re_held.unchecked<1>();
    const auto im = im_held.unchecked<1>();
    for (py::ssize_t i = 0; i < rows; ++i) w(i, k) = {re(i), im(i)};
  }
  return out;
}

// An orbit document (orbit --json) with arrays where orbits() has arrays:
// impact_times, x, v, and the multipliers as complex numbers.
py::dict OrbitRecordDict(const OrbitRecord& r) {
  py::dict d = ToPython(report::OrbitJson(r));
  const py::module_ np = py::module_::import("numpy");
  for (const char* k : {"impact_times", "x", "v"}) d[k] = np.attr("asarray")(d[k], "float64");
  if (r.stability) d["multipliers"] = Eigen::VectorXcd(r.stability->multipliers);
  return d;
}

// A grid from (from, to, step), "FROM:TO:STEP", or one value; errors name `field`.
PeriodGrid GridOf(const py::object& period, const std::string& field = "period") {
  if (IsBool(period)) throw py::type_error(field + ": must be a number or a grid, got " + Repr(period) + " (a bool)");
  if (py::isinstance<py::str>(period)) return PeriodGrid::Parse(period.cast<std::string>(), field);
  if (py::isinstance<py::float_>(period) || py::isinstance<py::int_>(period)) {
    const double t = period.cast<double>();
    PeriodGrid g{t, t, 1.0};
    g.Validate(field);
    return g;
  }
  if (py::isinstance<py::array>(period)) {
    // A NumPy array holds the periods themselves (np.arange, np.linspace),
    // evenly spaced: the grid (first, last, spacing). A list or a tuple of
    // three stays (from, to, step).
    const py::array_t<double> a = py::array_t<double>::ensure(period);
    if (!a || a.ndim() != 1 || a.shape(0) < 1) throw InputError(field, "as an array, must be a 1-D array of periods");
    const auto r = a.unchecked<1>();
    const py::ssize_t n = a.shape(0);
    PeriodGrid g{r(0), r(n - 1), n > 1 ? (r(n - 1) - r(0)) / static_cast<double>(n - 1) : 1.0};
    for (py::ssize_t k = 0; k < n; ++k) {
      // Evenly spaced to the round-off of np.arange / np.linspace (a few
      // ulps of the largest value), far below any step that makes sense.
      if (!(std::abs(r(k) - (g.from + static_cast<double>(k) * g.step)) <= 1e-9 * std::max(std::abs(g.step), 1e-300) +
                                                                                16 * 2.2e-16 * std::abs(g.to))) {
        throw InputError(field, "an array of periods must be evenly spaced (a grid), got " + FormatValue(r(k)) +
                                    " at index " + std::to_string(k));
      }
    }
    g.Validate(field);
    if (g.Count() != n) throw InputError(field, "an array of " + std::to_string(n) + " periods gives a grid of " + std::to_string(g.Count()));
    return g;
  }
  std::vector<double> v;
  try {
    v = period.cast<std::vector<double>>();
  } catch (const py::cast_error&) {
    throw InputError(field, "expects (from, to, step), 'FROM:TO:STEP' or one value");
  }
  if (v.size() != 3) throw InputError(field, "expects (from, to, step), got " + std::to_string(v.size()) + " values");
  PeriodGrid g{v[0], v[1], v[2]};
  g.Validate(field);
  return g;
}

// A keyword's value of the setting's kind (settings.h), with the checks of
// Real and Integer: a bool is not a number, a str is not a list.
SettingValue KeywordValue(py::handle h, const SettingInfo& info) {
  const char* name = info.python.c_str();
  auto list = [&](auto one) {
    if (py::isinstance<py::str>(h) || !py::isinstance<py::iterable>(h)) {
      throw py::type_error(std::string(name) + ": must be a sequence, got " + Repr(h));
    }
    std::vector<decltype(one(h))> out;
    for (py::handle item : h) out.push_back(one(item));
    return out;
  };
  auto text = [name](py::handle x) {
    if (!py::isinstance<py::str>(x)) throw py::type_error(std::string(name) + ": must be a str, got " + Repr(x));
    return x.cast<std::string>();
  };
  auto real = [name](py::handle x) { return RealOf(x, name); };
  auto integer = [name](py::handle x) { return static_cast<long>(IntOf(x, name)); };
  switch (info.kind) {
    case SettingKind::kReal: return real(h);
    case SettingKind::kInteger: return integer(h);
    case SettingKind::kText: return text(h);
    case SettingKind::kRealList: return list(real);
    case SettingKind::kIntegerList: return list(integer);
    case SettingKind::kTextList: return list(text);
  }
  throw std::logic_error("a setting kind without a Python conversion");
}

// The keywords of a call, as settings given by keyword (settings.h): each one
// the table's keyword of a setting `command` takes, else TypeError as Python
// raises for an unexpected keyword. `convert` may take a keyword first (a
// period given as a number or a tuple), returning no value to decline it.
template <class Options>
SettingPatch KeywordPatch(const SettingTable<Options>& table, const std::string& command, const py::dict& kwargs,
                          const std::function<std::optional<SettingValue>(const std::string&, py::handle)>& convert = {}) {
  SettingPatch patch;
  for (auto [key, value] : kwargs) {
    const std::string keyword = py::str(key);
    const Setting<Options>* s = table.FindKeyword(keyword);
    if (s == nullptr || !s->info.Takes(command)) {
      throw py::type_error(command + "() got an unexpected keyword argument '" + keyword + "'");
    }
    if (value.is_none()) continue;  // None: the scene's or the default value
    std::optional<SettingValue> v = convert ? convert(keyword, value) : std::nullopt;
    patch[s->info.name] = {v ? *v : KeywordValue(value, s->info), keyword, SettingSource::kKeyword};
  }
  return patch;
}

// The keywords' part of a docstring, from the table.
template <class Options>
std::string KeywordDoc(const SettingTable<Options>& table, const std::string& command) {
  std::string doc = "\n\nKeywords (`nsmodal.settings()` lists them with their scene keys and flags):\n";
  for (const Setting<Options>& s : table.settings()) {
    const SettingInfo& i = s.info;
    if (i.python.empty() || !i.Takes(command)) continue;
    doc += "  " + i.python + " (" + ToString(i.kind) + (i.unit.empty() ? "" : ", " + i.unit) + "; default " +
           FormatSettingValue(table.Default(s)) + "): " + i.doc + "\n";
  }
  return doc;
}

StabilityPolicy PolicyOf(const std::string& name) {
  if (name == "none") return StabilityPolicy::kNone;
  if (name == "potential") return StabilityPolicy::kPotential;
  if (name == "admissible") return StabilityPolicy::kAdmissible;
  throw InputError("stability", "expects 'none', 'potential' or 'admissible', got '" + name + "'");
}

Eigen::VectorXd VectorOf(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<long>(v.size()));
}

// The keywords' names in errors: the keyword where Python names its own
// checks, else the scene's field (system.contact_dof, as Validate names it).
FieldNames ModelKeywordNames() {
  FieldNames names("system.");
  for (const char* key : {"masses", "springs", "mass_matrix", "stiffness_matrix", "damping", "rayleigh_damping",
                          "forcing.amplitude", "forcing.frequency"}) {
    names.Set(key, key);
  }
  names.Set("contact", "contacts");
  return names.Set("form", "masses");
}

// sequence=[1, 2] (contact numbers) as the text ParseSequence reads; None: none.
std::optional<std::string> SequenceText(const py::object& sequence) {
  if (sequence.is_none()) return std::nullopt;
  if (py::isinstance<py::str>(sequence)) return sequence.cast<std::string>();
  std::string text;
  for (py::handle item : sequence.cast<py::iterable>()) {
    text += (text.empty() ? "" : ",") + std::to_string(IntOf(item, "sequence"));
  }
  return text;
}

// A parameter's range as the text ParseParameterRange reads: 'FROM:TO[:STEP]'
// as given, a tuple (from, to[, step]) written to 17 digits (read back
// exactly). Throws InputError naming `argument`.
std::string RangeText(const py::object& range, const std::string& argument) {
  if (py::isinstance<py::str>(range)) return range.cast<std::string>();
  if (!py::isinstance<py::sequence>(range) || IsBool(range)) {
    throw InputError(argument, "must be (from, to), (from, to, step) or 'FROM:TO[:STEP]', got " + Repr(range));
  }
  std::string text;
  const py::sequence seq = range.cast<py::sequence>();
  for (std::size_t k = 0; k < seq.size(); ++k) {
    const py::object v = seq[k];
    if (IsBool(v) || !(py::isinstance<py::float_>(v) || py::isinstance<py::int_>(v))) {
      throw InputError(argument, "must hold numbers, got " + Repr(range));
    }
    text += (k ? ":" : "") + FormatValue(v.cast<double>());
  }
  return text;
}

// contacts=[dict(dof=2, side="upper", gap=1.0, restitution=1.0), ...]: each
// dict a scene's [[contact]] table (model_spec.h), its keys checked here.
std::optional<std::vector<ContactSpec>> ContactSpecs(const std::optional<py::list>& contacts) {
  if (!contacts) return std::nullopt;
  std::vector<ContactSpec> specs;
  for (std::size_t j = 0; j < contacts->size(); ++j) {
    const std::string at = "contacts[" + std::to_string(j) + "]";
    const py::handle item = (*contacts)[j];
    if (!py::isinstance<py::dict>(item)) {
      throw py::type_error(at + ": must be a dict (dof=, side=, between=, normal=, gap=, restitution=), got " +
                           Repr(item));
    }
    ContactSpec c;
    for (auto [key, value] : item.cast<py::dict>()) {
      const std::string k = py::str(key);
      const std::string name = at + "['" + k + "']";
      auto list = [&] {
        std::vector<double> v;
        for (py::handle x : value.cast<py::iterable>()) v.push_back(RealOf(x, name.c_str()));
        return v;
      };
      if (k == "dof") {
        c.dof = IntOf(value, name.c_str());
      } else if (k == "side") {
        if (!py::isinstance<py::str>(value)) throw py::type_error(name + ": must be \"upper\" or \"lower\", got " + Repr(value));
        c.side = value.cast<std::string>();
      } else if (k == "between") {
        c.between = list();
      } else if (k == "normal") {
        c.normal = list();
      } else if (k == "gap") {
        c.gap = RealOf(value, name.c_str());
      } else if (k == "restitution") {
        c.restitution = RealOf(value, name.c_str());
      } else {
        throw py::type_error(at + ": unexpected key '" + k + "' (dof, side, between, normal, gap, restitution)");
      }
    }
    specs.push_back(std::move(c));
  }
  return specs;
}

// A contact as the dict contacts= takes (its form as written).
py::dict ContactDict(const Contact& c) {
  py::dict d;
  switch (c.form) {
    case Contact::Form::kDof:
      d["dof"] = c.dof + 1;
      d["side"] = c.upper ? "upper" : "lower";
      break;
    case Contact::Form::kBetween: d["between"] = py::make_tuple(c.dof + 1, c.other + 1); break;
    case Contact::Form::kNormal: d["normal"] = c.normal; break;
  }
  d["gap"] = c.gap;
  d["restitution"] = c.restitution;
  return d;
}

Model MakeModel(std::optional<std::vector<double>> masses, std::optional<std::vector<double>> springs,
                std::optional<Eigen::MatrixXd> mass_matrix, std::optional<Eigen::MatrixXd> stiffness_matrix,
                std::optional<Real<"gap">> gap, std::optional<Real<"restitution">> restitution,
                std::optional<Integer<"contact_dof">> contact_dof, std::optional<py::list> contacts,
                std::optional<std::vector<double>> rayleigh_damping, std::optional<std::vector<double>> damping_ratios,
                std::optional<Eigen::MatrixXd> damping_matrix, std::optional<std::vector<double>> forcing_amplitude,
                std::optional<Real<"forcing_frequency">> forcing_frequency,
                std::optional<std::vector<double>> forcing_constant) {
  ModelSpec spec{.masses = std::move(masses),
                 .springs = std::move(springs),
                 .mass_matrix = std::move(mass_matrix),
                 .stiffness_matrix = std::move(stiffness_matrix),
                 .bar = std::nullopt,
                 .contact_dof = contact_dof ? std::optional<double>(*contact_dof) : std::nullopt,
                 .gap = gap ? std::optional<double>(*gap) : std::nullopt,
                 .restitution = restitution ? std::optional<double>(*restitution) : std::nullopt,
                 .contacts = ContactSpecs(contacts),
                 .rayleigh_damping = std::move(rayleigh_damping),
                 .damping_ratios = std::move(damping_ratios),
                 .damping_matrix = std::move(damping_matrix),
                 .forcing_amplitude = std::move(forcing_amplitude),
                 .forcing_frequency = forcing_frequency ? std::optional<double>(*forcing_frequency) : std::nullopt,
                 .forcing_constant = std::move(forcing_constant)};
  return AssembleModel(spec, ModelKeywordNames());
}

// The response grid and the fixed parameter: one of frequency and amplitude
// is a grid, the other one value or, when None, the model's own.
ResponseOptions ResponseOptionsOf(const Model& model, int impacts, int periods, const py::object& frequency,
                                  const py::object& amplitude, const py::object& sequence) {
  if (IsBool(frequency) || IsBool(amplitude)) {
    const bool f = IsBool(frequency);
    throw py::type_error(std::string(f ? "frequency" : "amplitude") + ": must be a number or a grid, got " +
                         Repr(f ? frequency : amplitude) + " (a bool)");
  }
  auto is_grid = [](const py::object& o) {
    return !o.is_none() && !py::isinstance<py::float_>(o) && !py::isinstance<py::int_>(o);
  };
  if (is_grid(frequency) == is_grid(amplitude)) {
    throw InputError("frequency", "give exactly one of frequency and amplitude as a grid (from, to, step) or "
                                  "'FROM:TO:STEP', the other as one value (or None: the model's forcing)");
  }
  const bool f = is_grid(frequency);
  const PeriodGrid grid = GridOf(f ? frequency : amplitude, f ? "frequency" : "amplitude");
  const py::object& held = f ? amplitude : frequency;
  std::vector<double> level;
  if (!held.is_none()) level.push_back(held.cast<double>());
  return MakeResponseRequest(model, f ? ResponseParameter::kFrequency : ResponseParameter::kAmplitude, grid, level,
                             impacts, periods, FieldNames(), SequenceText(sequence))
      .options;
}

}  // namespace

// Long work runs without the GIL on a worker thread while this thread, the
// one Python delivers signals to, checks for them every 50 ms: Ctrl-C (or
// Jupyter's "interrupt kernel") runs Python's SIGINT handler in
// PyErr_CheckSignals, which sets KeyboardInterrupt; the work is then asked to
// stop (stop.h: every long loop polls between units of work, so it unwinds
// within a fraction of a second), awaited, and the KeyboardInterrupt raised.
// The stop request is cleared, so the next call runs. Called from another
// Python thread, PyErr_CheckSignals never reports a signal: the call then
// runs to its end, as any call without this did. The stop request is the
// process's (stop.h): a Ctrl-C stops every call running at that moment, in
// any Python thread, not only the one that saw it.
template <class F>
auto Interruptible(F&& work) -> decltype(work()) {
  using R = decltype(work());
  std::packaged_task<R()> task(std::forward<F>(work));
  std::future<R> done = task.get_future();
  std::thread worker;
  {
    py::gil_scoped_release release;
    worker = std::thread(std::move(task));
  }
  for (;;) {
    bool ready = false;
    {
      py::gil_scoped_release release;
      ready = done.wait_for(std::chrono::milliseconds(50)) == std::future_status::ready;
    }
    if (ready) break;
    if (PyErr_CheckSignals() != 0) {
      RequestStop(SIGINT);
      {
        py::gil_scoped_release release;
        worker.join();
      }
      ClearStopRequest();
      throw py::error_already_set();
    }
  }
  worker.join();
  return done.get();  // the work's own exception, if it threw, translated as usual
}

// A docstring that starts with its text signature ("name(args)\n--\n\n"),
// from which CPython makes __text_signature__, so that inspect.signature()
// and help() show the arguments (pybind11's own signature lines are off:
// they are not in that form). Kept for the module's life.
const char* Signed(const std::string& signature, const std::string& doc) {
  static std::deque<std::string> docs;
  docs.push_back(signature + "\n--\n\n" + doc);
  return docs.back().c_str();
}

// A setting's default as a Python literal, for a text signature.
std::string PythonLiteral(const SettingValue& value) {
  struct Visitor {
    std::string operator()(std::monostate) const { return "None"; }
    std::string operator()(double v) const { return FormatSettingValue(v); }
    std::string operator()(long v) const { return std::to_string(v); }
    std::string operator()(const std::string& v) const { return "'" + v + "'"; }
    std::string operator()(const std::vector<double>& v) const { return v.empty() ? "None" : FormatSettingValue(v); }
    std::string operator()(const std::vector<long>& v) const { return FormatSettingValue(v); }
    std::string operator()(const std::vector<std::string>& v) const {
      std::string out = "[";
      for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", '" : "'") + v[i] + "'";
      return out + "]";
    }
  };
  return std::visit(Visitor{}, value);
}

// "name(head, *, keyword=default, ...)": the keywords of `command` in the
// table's order, those already in `head` left out.
template <class Options>
std::string TextSignature(const std::string& name, const std::string& head, const std::vector<std::string>& in_head,
                          const std::string& extra, const SettingTable<Options>& table, const std::string& command) {
  std::string sig = name + "(" + head + ", *" + (extra.empty() ? "" : ", " + extra);
  for (const Setting<Options>& s : table.settings()) {
    const SettingInfo& i = s.info;
    if (i.python.empty() || !i.Takes(command)) continue;
    if (std::find(in_head.begin(), in_head.end(), i.python) != in_head.end()) continue;
    sig += ", " + i.python + "=" + PythonLiteral(table.Default(s));
  }
  return sig + ")";
}

// A Python callable as a progress callback of the library (None: none):
// called as progress(done, total) from the worker threads, each call with
// the GIL. An exception it raises ends the call and reaches the caller.
std::function<void(long, long)> ProgressOf(const py::object& progress) {
  if (progress.is_none()) return {};
  if (!PyCallable_Check(progress.ptr())) throw py::type_error("progress: must be callable, got " + Repr(progress));
  return [progress](long done, long total) {
    py::gil_scoped_acquire acquire;
    progress(done, total);
  };
}

PYBIND11_MODULE(_nsmodal, mod) {
  // Every docstring states its own text signature (Signed).
  py::options options;
  options.disable_function_signatures();
  // The visual language (report/style.toml, compiled in) for nsmodal.style.
  mod.def("_style_json", [] { return report::style::Json(); },
          "_style_json() -> str\n\nreport/style.toml as JSON (read by nsmodal.style).");
  mod.doc() = R"doc(nsmodal: nonsmooth modal analysis of vibro-impact oscillators.

Masses and springs, one rigid obstacle x_c <= d, a Newton impact law
v_c(t+) = -e v_c(t-). Periodic orbits with m impacts per period come from the
kernel of the return map A_m (Thorin, Legrand, Junca 2015); families of them,
drawn in frequency-energy plots, are the system's nonsmooth modes.

    import nsmodal
    m = nsmodal.load_scene("configs/paper.toml")
    m.linear_periods                       # array([ 2.97..., 10.18...])
    o = nsmodal.orbits(m, impacts=1, period=(0.05, 40.0, 0.01))
    o["T"][o["admissible"]], o["energy"][o["admissible"]]
    tr = nsmodal.transitions(m, period=(0.05, 40.0, 0.01))
    s = nsmodal.simulate(m, x0=[0.5, 0.0], v0=[0.5, 1.2], t_end=1000.0)

Bad input raises ValueError naming the field (as a scene file or the CLI
would name it), TypeError naming the keyword for a value of the wrong type
(a bool where a number or a count is asked: gap=True, impacts=True); a file
that cannot be written raises OSError. Missing values: NaN in the float
columns of a table (as pandas.read_csv reads the CSV's empty fields), None in
a document's dict; never inf or NaN as a value.)doc";

  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const report::OutputError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    }
  });

  py::class_<Model>(mod, "Model", R"doc(A vibro-impact system: M x'' + C x' + K x = f0 + f cos(w t) in flight,
contacts g_j = d_j - n_j . x >= 0, each with Newton's law.

Model(masses=None, springs=None, mass_matrix=None, stiffness_matrix=None, *,
      gap=None, restitution=None, contact_dof=None, contacts=None,
      rayleigh_damping=None, damping_ratios=None, damping_matrix=None,
      forcing_amplitude=None, forcing_frequency=None, forcing_constant=None)

Either a chain (masses m_1..m_N and springs ground-m_1, m_1-m_2, ...) or
symmetric positive-definite mass and stiffness matrices. One stop x_c <= d:
gap d > 0, restitution e in [0, 1], contact_dof 1-based (default: the last
dof). Or several contacts, numbered from 1 in the order given:
contacts=[dict(dof=2, side="upper", gap=1.0, restitution=1.0),
dict(dof=2, side="lower", gap=1.0, restitution=1.0),
dict(between=(1, 2), gap=0.2, restitution=0.6),
dict(normal=[...], gap=..., restitution=...)], as the scene's [[contact]]
tables ("lower": x >= -gap; between=(a, b): x_a - x_b <= gap). Nonsmooth-mode
analysis needs e = 1 (one contact, for now), no damping, no force; simulation
takes any e and any number of contacts. Damping, at most one of: rayleigh_damping (a, b): C = a M + b K;
damping_ratios: one per linear mode; damping_matrix: any symmetric positive
semi-definite C. Forcing: f = forcing_amplitude (N values) at
w = forcing_frequency, f0 = forcing_constant.)doc")
      .def(py::init(&MakeModel), py::arg("masses") = py::none(), py::arg("springs") = py::none(),
           py::arg("mass_matrix") = py::none(), py::arg("stiffness_matrix") = py::none(), py::kw_only(),
           py::arg("gap") = py::none(), py::arg("restitution") = py::none(), py::arg("contact_dof") = py::none(),
           py::arg("contacts") = py::none(), py::arg("rayleigh_damping") = py::none(), py::arg("damping_ratios") = py::none(),
           py::arg("damping_matrix") = py::none(), py::arg("forcing_amplitude") = py::none(),
           py::arg("forcing_frequency") = py::none(), py::arg("forcing_constant") = py::none(),
           Signed("__init__(self, /, masses=None, springs=None, mass_matrix=None, stiffness_matrix=None, *, gap=None, "
                  "restitution=None, contact_dof=None, contacts=None, rayleigh_damping=None, damping_ratios=None, damping_matrix=None, "
                  "forcing_amplitude=None, forcing_frequency=None, forcing_constant=None)",
                  "A Model from a chain or from matrices (see the class)."))
      .def_property_readonly("damping_matrix", [](const Model& m) { return m.DampingMatrix(); }, "C (N x N; zero: none).")
      .def_property_readonly("forcing_amplitude", [](const Model& m) { return m.ForceAmplitude(); }, "f (zero: none).")
      .def_property_readonly("forcing_frequency", [](const Model& m) { return m.forcing.frequency; }, "w.")
      .def_property_readonly("forcing_constant", [](const Model& m) { return m.ConstantForce(); }, "f0 (zero: none).")
      .def_property_readonly("dofs", &Model::dofs, "Number of degrees of freedom N.")
      .def_property_readonly("mass_matrix", [](const Model& m) { return m.mass; }, "M (N x N).")
      .def_property_readonly("stiffness_matrix", [](const Model& m) { return m.stiffness; }, "K (N x N).")
      .def_property_readonly("contact_dof", [](const Model& m) { return m.FirstContact().PlotDof() + 1; },
                             "c, 1-based: contact 1's dof.")
      .def_property_readonly("gap", [](const Model& m) { return m.FirstContact().gap; }, "d: contact 1's gap.")
      .def_property_readonly("restitution", [](const Model& m) { return m.FirstContact().restitution; },
                             "e: contact 1's restitution.")
      .def_property_readonly(
          "contacts",
          [](const Model& m) {
            py::list out;
            for (const Contact& c : m.contacts) out.append(ContactDict(c));
            return out;
          },
          "The contacts as dicts (the contacts= keyword's form), contact 1 first.")
      .def_property_readonly(
          "linear_periods",
          [](const Model& m) {
            Eigen::VectorXd t = MakeModalBasis(m).Periods();
            std::sort(t.data(), t.data() + t.size());
            return t;
          },
          "Periods 2 pi / w_i of the linear modes, ascending (NumPy array).")
      .def(
          "replace",
          [](const Model& m, const py::kwargs& changes) {
            // The constructor's keywords; the current model's matrices,
            // contact and forcing are the defaults a change overrides.
            static const char* keywords[] = {"masses", "springs", "mass_matrix", "stiffness_matrix", "gap",
                                             "restitution", "contact_dof", "contacts", "rayleigh_damping", "damping_ratios",
                                             "damping_matrix", "forcing_amplitude", "forcing_frequency",
                                             "forcing_constant"};
            for (auto [key, value] : changes) {
              const std::string k = py::str(key);
              if (std::find_if(std::begin(keywords), std::end(keywords), [&](const char* w) { return k == w; }) ==
                  std::end(keywords)) {
                throw py::type_error("replace() got an unexpected keyword argument '" + k + "'");
              }
            }
            py::dict kw;
            if (!changes.contains("masses") && !changes.contains("springs")) {
              kw["mass_matrix"] = m.mass;
              kw["stiffness_matrix"] = m.stiffness;
            }
            // The contacts as they were written (the shorthand's keys
            // override one by one; contacts= replaces them all).
            const bool shorthand = m.NumContacts() == 1 && m.FirstContact().shorthand;
            const bool new_shorthand = changes.contains("gap") || changes.contains("restitution") ||
                                       changes.contains("contact_dof");
            if (changes.contains("contacts") && new_shorthand) {
              throw InputError("contacts", "give either contacts= or the one-contact keywords (gap, restitution, "
                                           "contact_dof), not both");
            }
            if (!changes.contains("contacts")) {
              if (shorthand) {
                kw["gap"] = m.FirstContact().gap;
                kw["restitution"] = m.FirstContact().restitution;
                kw["contact_dof"] = m.FirstContact().dof + 1;
              } else if (new_shorthand) {
                throw InputError("contacts", "this model's contacts were given as contacts=[...]: change them with "
                                             "contacts=, not with gap, restitution or contact_dof");
              } else {
                py::list list;
                for (const Contact& c : m.contacts) list.append(ContactDict(c));
                kw["contacts"] = list;
              }
            }
            const bool new_damping = changes.contains("rayleigh_damping") || changes.contains("damping_ratios") ||
                                     changes.contains("damping_matrix");
            if (m.HasDamping() && !new_damping) kw["damping_matrix"] = m.damping;
            if (m.forcing.HasHarmonic()) {
              kw["forcing_amplitude"] = m.forcing.amplitude;
              kw["forcing_frequency"] = m.forcing.frequency;
            }
            if (m.forcing.HasConstant()) kw["forcing_constant"] = m.forcing.constant;
            for (auto [key, value] : changes) kw[key] = value;
            return py::type::of<Model>()(**kw).cast<Model>();
          },
          Signed("replace($self, /, **changes)", R"doc(A copy with some of the constructor's keywords changed: m.replace(gap=0.5),
m.replace(restitution=0.8, rayleigh_damping=(0.0, 0.01)). masses and springs
replace the matrices; a damping form replaces the damping. Checked as a new
Model is.)doc"))
      // Pickling (multiprocessing, joblib, copy): the matrices, the forcing and
      // the contacts; a state is checked on the way in as a new Model is.
      .def(py::pickle(
          [](const Model& m) {
            py::list contacts;
            for (const Contact& c : m.contacts) {
              contacts.append(py::make_tuple(static_cast<int>(c.form), c.dof, c.other, c.upper, c.normal, c.gap,
                                             c.restitution, c.shorthand));
            }
            return py::make_tuple(2, m.mass, m.stiffness, m.damping, m.forcing.constant, m.forcing.amplitude,
                                  m.forcing.frequency, contacts);
          },
          [](const py::tuple& t) {
            if (t.size() != 8 || t[0].cast<int>() != 2) throw InputError("state", "is not a pickled nsmodal.Model");
            Model m;
            m.mass = t[1].cast<Eigen::MatrixXd>();
            m.stiffness = t[2].cast<Eigen::MatrixXd>();
            m.damping = t[3].cast<Eigen::MatrixXd>();
            m.forcing.constant = t[4].cast<Eigen::VectorXd>();
            m.forcing.amplitude = t[5].cast<Eigen::VectorXd>();
            m.forcing.frequency = t[6].cast<double>();
            for (py::handle h : t[7].cast<py::list>()) {
              const py::tuple c = h.cast<py::tuple>();
              const int form = c[0].cast<int>();
              if (c.size() != 8 || form < 0 || form > 2) throw InputError("state", "is not a pickled nsmodal.Model");
              Contact k;
              k.form = static_cast<Contact::Form>(form);
              k.dof = c[1].cast<int>();
              k.other = c[2].cast<int>();
              k.upper = c[3].cast<bool>();
              k.normal = c[4].cast<Eigen::VectorXd>();
              k.gap = c[5].cast<double>();
              k.restitution = c[6].cast<double>();
              k.shorthand = c[7].cast<bool>();
              m.contacts.push_back(std::move(k));
            }
            Validate(m);
            return m;
          }))
      .def("__repr__", [](const Model& m) {
        if (m.NumContacts() > 1 || !m.FirstContact().shorthand) {
          std::string text = "<nsmodal.Model: " + std::to_string(m.dofs()) + " dofs, contacts";
          for (const Contact& c : m.contacts) text += " " + c.Describe() + " (e = " + FormatValue(c.restitution) + ");";
          text.back() = '>';
          return text;
        }
        return "<nsmodal.Model: " + std::to_string(m.dofs()) + " dofs, contact_dof " +
               std::to_string(m.FirstContact().dof + 1) + ", gap " + FormatValue(m.FirstContact().gap) +
               ", restitution " + FormatValue(m.FirstContact().restitution) + ">";
      });

  mod.def(
      "bar",
      [](Real<"length"> length, Real<"youngs_modulus"> youngs_modulus, Real<"density"> density, Real<"area"> area,
         Integer<"elements"> elements, const std::string& boundary, const std::string& mass,
         std::optional<Integer<"contact_dof">> contact_dof, std::optional<Real<"gap">> gap,
         std::optional<Real<"restitution">> restitution, std::optional<py::list> contacts) {
        BarSpec bar;
        bar.length = length;
        bar.youngs_modulus = youngs_modulus;
        bar.density = density;
        bar.area = area;
        bar.elements = elements;
        bar.boundary = ParseBarBoundary(boundary, "boundary");
        bar.mass = ParseBarMass(mass, "mass");
        ModelSpec spec;
        spec.bar = bar;
        if (contact_dof) spec.contact_dof = *contact_dof;
        if (gap) spec.gap = *gap;
        if (restitution) spec.restitution = *restitution;
        spec.contacts = ContactSpecs(contacts);
        return AssembleModel(spec, ModelKeywordNames());
      },
      py::kw_only(), py::arg("length"), py::arg("youngs_modulus"), py::arg("density"), py::arg("area"),
      py::arg("elements"), py::arg("boundary") = "fixed-free", py::arg("mass") = "consistent",
      py::arg("contact_dof") = py::none(), py::arg("gap") = py::none(), py::arg("restitution") = py::none(),
      py::arg("contacts") = py::none(),
      Signed("bar(*, length, youngs_modulus, density, area, elements, boundary='fixed-free', mass='consistent', "
             "contact_dof=None, gap=None, restitution=None, contacts=None)", R"doc(A uniform elastic bar in axial vibration by linear finite elements (the
scene's [system] bar): `elements` elements, one node per element end;
boundary "fixed-free" (node 0 clamped; dofs = nodes 1..n) or "free-free"
(dofs = nodes 0..n, one rigid-body mode: simulation only); mass
"consistent" or "lumped". contact_dof is 1-based (default: the last node);
contacts=[...] gives several contacts instead, as Model's.)doc"));

  py::class_<ModalTruncation>(mod, "ModalTruncation", R"doc(The first k linear modes of a model as a model of k
dofs (truncation.h): `model` (its dof 1 is x_c), `to_physical` (N x k: x =
to_physical p), `from_physical` (k x N), `kept`, `dofs`, the frequencies on
either side of the cut, `residual_flexibility` f_res, and contact_bound(E) =
sqrt(2 E f_res): the most the neglected modes add to x_c in a state of the
full model with energy E.)doc")
      .def_readonly("model", &ModalTruncation::model)
      .def_readonly("to_physical", &ModalTruncation::to_physical)
      .def_readonly("from_physical", &ModalTruncation::from_physical)
      .def_readonly("kept", &ModalTruncation::kept)
      .def_readonly("dofs", &ModalTruncation::dofs)
      .def_readonly("highest_kept_frequency", &ModalTruncation::highest_kept_frequency)
      .def_readonly("lowest_neglected_frequency", &ModalTruncation::lowest_neglected_frequency)
      .def_readonly("residual_flexibility", &ModalTruncation::residual_flexibility)
      .def("contact_bound", &ModalTruncation::ContactBound, py::arg("energy"),
           Signed("contact_bound($self, /, energy)",
                  "sqrt(2 E f_res): the most the neglected modes can add to x_c in a state of the full model with "
                  "energy E (J)."));

  mod.def(
      "truncate",
      [](const Model& model, std::optional<Integer<"modes">> modes,
         std::optional<Real<"contact_tolerance">> contact_tolerance, std::optional<Real<"energy">> energy) {
        if (modes.has_value() == contact_tolerance.has_value()) {
          throw InputError("modes", "give modes or contact_tolerance (with energy), one of them");
        }
        if (contact_tolerance && !energy) throw InputError("energy", "is needed with contact_tolerance");
        return modes ? TruncateModes(model, *modes, "modes")
                     : TruncateForContactBound(model, *energy, *contact_tolerance, "contact_tolerance");
      },
      py::arg("model"), py::kw_only(), py::arg("modes") = py::none(), py::arg("contact_tolerance") = py::none(),
      py::arg("energy") = py::none(),
      Signed("truncate(model, *, modes=None, contact_tolerance=None, energy=None)", R"doc(Modal truncation: the first `modes` linear modes, or the fewest whose
contact_bound(energy) is at most contact_tolerance (m). Returns a
ModalTruncation; simulate its `model` from from_physical @ x0.)doc"));

  mod.def(
      "load_scene", [](const std::string& path) { return LoadScene(path, "path").model; }, py::arg("path"),
      Signed("load_scene(path)", R"doc(The model of a scene: a file (TOML, the [system] table; see configs/paper.toml)
or the name of an example scene compiled into nsmodal (scenes() lists them:
load_scene("paper") is the paper's system, wherever nsmodal is installed).
The CLI's reader: a regular file of at most 16 MiB; a FIFO, a device, a
directory, a larger file or a path holding a NUL raise ValueError naming
`path`.)doc"));

  mod.def(
      "scenes",
      [] {
        py::list names;
        for (const auto& [name, text] : BuiltinScenes()) names.append(name);
        return names;
      },
      Signed("scenes()", R"doc(The names of the example scenes compiled into nsmodal (configs/*.toml).)doc"));

  mod.def(
      "orbits",
      [](const Model& model, Integer<"impacts"> impacts, const py::object& period, const std::string& stability,
         Integer<"threads"> threads, bool all_multipliers, const py::object& progress, const py::object& sequence) {
        CheckThreads(threads, "threads");
        const AnalysisBasis b(model);
        const PeriodGrid grid = GridOf(period);
        SweepOptions opt;
        int m = impacts;
        std::tie(m, opt.sequence) = ImpactSequence(impacts, SequenceText(sequence),
                                                   static_cast<int>(b.contacts.size()), FieldNames());
        opt.stability = PolicyOf(stability);
        opt.stability_options.all_multipliers = all_multipliers;
        opt.threads = threads;
        opt.progress = ProgressOf(progress);
        const Sweep sweep = Interruptible([&] { return ComputeSweep(b, grid, m, opt); });
        return OrbitsDict(sweep, b.n);
      },
      py::arg("model"), py::arg("impacts") = 1, py::arg("period"), py::arg("stability") = "potential",
      py::arg("threads") = 0, py::arg("all_multipliers") = true, py::arg("progress") = py::none(),
      py::arg("sequence") = py::none(),
      Signed("orbits(model, impacts=1, *, period, stability='potential', threads=0, all_multipliers=True, progress=None, "
             "sequence=None)", R"doc(Potential orbits with 1 or 2 impacts per period over a grid of periods.

sequence: with several contacts, the contact of each impact (numbered from 1
as given), e.g. [1, 2]; None: every impact on contact 1 (impacts= of them).

period: (from, to, step), "FROM:TO:STEP", one period T, or a NumPy array of
evenly spaced periods (np.arange, np.linspace).
stability: which orbits get Floquet multipliers: "potential" (default),
"admissible" or "none".
all_multipliers: False keeps, for 1 impact, only the verdict, the largest
modulus and the multipliers off the unit circle (the others are NaN in the
mu columns): less work for large systems.
progress: None or a callable progress(done, total), called as periods are done.

Returns a dict of NumPy arrays, one entry per orbit, keyed as the columns of
orbits.csv: "T", "t2" (NaN for one impact), "energy", "potential",
"admissible", "periodicity_residual", "nc2_residual", "nc3_margin",
"degenerate", "x1".."xN", "v1".."vN" (the state just after the impact at
t = 0), "stable" (False where not computed), "max_multiplier" (NaN where not
computed), "mu1_re", "mu1_im", ... (sorted by decreasing modulus). Every
entry is a 1-D array: pandas.DataFrame(o) takes it whole; stack(o, "x"),
stack(o, "v") and stack(o, "mu") give the state (rows x N) and the
multipliers (rows x 2N, complex) as matrices.
Needs restitution = 1 (ValueError naming system.restitution otherwise).)doc"));

  mod.def(
      "orbit",
      [](const Model& model, Real<"period"> period, Integer<"impacts"> impacts, const py::object& sequence) {
        const AnalysisBasis b(model);
        SweepOptions opt;
        int m = impacts;
        std::tie(m, opt.sequence) = ImpactSequence(impacts, SequenceText(sequence),
                                                   static_cast<int>(b.contacts.size()), FieldNames());
        PeriodGrid{period, period, 1.0}.Validate("period");
        py::list out;
        for (const OrbitRecord& r : OrbitsAt(b, period, m, opt)) out.append(OrbitRecordDict(r));
        return out;
      },
      py::arg("model"), py::arg("period"), py::arg("impacts") = 1, py::arg("sequence") = py::none(),
      Signed("orbit(model, period, impacts=1, sequence=None)", R"doc(Every potential orbit of period T as a list of dicts (as `nsmodal orbit --json`):
"T", "impact_times", "t2", "sequence" (the contact of each impact, from 1),
"energy", "potential", "admissible", "degenerate",
residuals, "nc3_margin", "x", "v", "reason", "stable", "max_multiplier",
"multipliers"; impact_times, x and v float arrays, the multipliers a complex
array, as in orbits().)doc"));

  mod.def("stack", &Stack, py::arg("table"), py::arg("name"),
          Signed("stack(table, name)", R"doc(Columns name1, name2, ... of a table as one matrix (rows x N):
stack(o, "x"), stack(o, "v") for the state of orbits() or of a trajectory;
stack(o, "mu") for the Floquet multipliers as a complex matrix (NaN where not
computed). Every table is a dict of 1-D arrays, so pandas.DataFrame(table)
takes it whole.)doc"));

  mod.def(
      "transitions",
      [](const Model& model, const py::object& period) {
        const AnalysisBasis b(model);
        const PeriodGrid grid = GridOf(period);
        const std::vector<Transition> tr = Interruptible([&] {
          SweepOptions opt;
          opt.stability = StabilityPolicy::kNone;
          return SweepTransitions(b, ComputeSweep(b, grid, 1, opt));
        });
        return TableDict(report::TransitionColumns(), Pointers(tr));
      },
      py::arg("model"), py::arg("period"),
      Signed("transitions(model, period)", R"doc(Transitions of the admissible 1-ipp zones seen on the grid (paper section 2.1),
and the stability changes inside them: dict of arrays "T", "kind" (list of
"singular", "modal", "grazing" -- the zones' ends -- and "multiplier+1",
"multiplier-1": a pair of Floquet multipliers through +1 or -1), "energy"
(NaN at a singular transition, where it diverges: an empty field in
transitions.csv); the rows of transitions.csv.)doc"));

  mod.def(
      "atlas",
      [](const Model& model, const py::object& period, Integer<"threads"> threads, const py::object& progress) {
        CheckThreads(threads, "threads");
        const AnalysisBasis b(model);
        const PeriodGrid grid = GridOf(period);
        AtlasOptions opt;
        opt.sweep.threads = threads;
        opt.sweep.progress = ProgressOf(progress);
        const Atlas a = Interruptible([&] { return ComputeAtlas(b, grid, opt); });
        py::dict d;
        d["one"] = OrbitsDict(a.one, b.n);
        d["two"] = OrbitsDict(a.two, b.n);
        d["transitions"] = TableDict(report::TransitionColumns(), Pointers(a.transitions));
        d["bridges"] = TableDict(report::BridgeColumns(), Pointers(a.bridges));
        d["doublings"] = VectorOf(a.doublings);
        d["notes"] = a.notes;
        return d;
      },
      py::arg("model"), py::arg("period"), py::arg("threads") = 0, py::arg("progress") = py::none(),
      Signed("atlas(model, period, threads=0, progress=None)", R"doc(The whole picture over a grid: dict with "one" and "two" (as orbits(),
stability of the admissible orbits), "transitions", "bridges" ("T", "t2",
"energy_min", "energy_max", "s_begin", "s_end", "kind"), "doublings" (the
periods T* where a 1-ipp orbit has a Floquet multiplier at -1) and "notes".
progress: None or a callable progress(done, total).)doc"));

  mod.def(
      "multipliers",
      [](const Model& model, Real<"period"> period, Integer<"impacts"> impacts, std::optional<Real<"t2">> t2) {
        const AnalysisBasis b(model);
        b.CheckPeriod(period);
        Orbit o;
        if (impacts == 1) {
          o = OneImpactOrbit(b, period);
        } else if (impacts == 2) {
          if (!t2) throw InputError("t2", "is needed for two impacts per period");
          const TwoImpactOptions two;
          if (!(TwoImpactKernelResidual(b, *t2, period) < two.kernel_tol)) {
            throw InputError("t2", "(t2, T) = (" + FormatValue(*t2) + ", " + FormatValue(period) +
                                       ") is not a root of det A_2 (see orbits(..., impacts=2))");
          }
          o = TwoImpactOrbitAt(b, *t2, period, two);
        } else {
          throw InputError("impacts", "multipliers takes 1 or 2, got " + std::to_string(impacts.value));
        }
        if (!o.potential) throw InputError("period", "no potential orbit at T = " + FormatValue(period) + ": " + o.reason);
        return Eigen::VectorXcd(OrbitStability(b, o).multipliers);
      },
      py::arg("model"), py::arg("period"), py::arg("impacts") = 1, py::arg("t2") = py::none(),
      Signed("multipliers(model, period, impacts=1, t2=None)", R"doc(Floquet multipliers (complex array, decreasing modulus) of the 1-ipp orbit of
period T, or of the 2-ipp orbit at the root (t2, T): eigenvalues of the
monodromy with the impact saltation matrices. Two are the trivial pair at 1.)doc"));

  static const std::string simulate_doc =
      R"doc(Simulate one initial condition, any restitution 0 <= e <= 1.

integrator: "exact" (closed-form flight, guaranteed impact search; root_tol),
"cvode" (SUNDIALS CVODE with root finding; its tolerances, method "adams"|"bdf")
or "moreau-jean" (time-stepping; step, theta). v0 defaults to rest. modes or
contact_tolerance: run on the first linear modes (modal truncation), every
state reported on the N dofs.

Returns the dict of summary.json ("status", "final_time", "final_state",
"impacts", "grazes", "zeno_events", "sticking_time", "energy_drift",
"settings", "settings_source", ...) plus "trajectory" (arrays "t",
"x1".."xN", "v1".."vN", "energy", every sample_dt) and "impact_log" (arrays
"t", "x1_before".., "x1_after"..), and "truncation" when modes were dropped.
on_impact: None or a callable on_impact(t, before, after) (the states
(x, v) just before and after, arrays of 2N) at each impact; progress: None
or a callable progress(t, t_end) as the run goes. As in SciPy's solve_ivp,
t_span=(t_start, t_end) may give t_end and a start time (x0, v0 taken at
t_start: a harmonic force starts at its phase w t_start), and t_eval=[...]
(ascending, in [t_start, t_end]) the trajectory's sample times instead of the
sample_dt grid; each sample is the exact state at that time (the closed-form
flight for "exact").
A run that stopped early has "status" != "finished" and says why in
"message".)doc" + KeywordDoc(SimulateSettings(), "simulate");
  mod.def(
      "simulate",
      [](const Model& model, const py::args& args, const py::kwargs& kwargs) {
        // x0 and v0 may come by position, as before the settings table.
        py::dict all = kwargs.attr("copy")();  // the caller's dict is left as it was
        const char* positional[] = {"x0", "v0"};
        if (args.size() > 2) throw py::type_error("simulate() takes at most 3 positional arguments (model, x0, v0)");
        for (std::size_t i = 0; i < args.size(); ++i) {
          if (all.contains(positional[i])) {
            throw py::type_error(std::string("simulate() got multiple values for argument '") + positional[i] + "'");
          }
          all[positional[i]] = args[i];
        }
        // The callables are not settings: taken out before the settings are read.
        const py::object on_impact = all.contains("on_impact") ? all.attr("pop")("on_impact") : py::none();
        const py::object progress = all.contains("progress") ? all.attr("pop")("progress") : py::none();
        for (const py::object& f : {on_impact, progress}) {
          if (!f.is_none() && !PyCallable_Check(f.ptr())) {
            throw py::type_error(std::string(f.is(on_impact) ? "on_impact" : "progress") + ": must be callable, got " +
                                 Repr(f));
          }
        }
        // SciPy's names (solve_ivp): t_span = (t_start, t_end), t_eval = the sample times.
        double t_start = 0.0;
        if (all.contains("t_span")) {
          const py::object span = all.attr("pop")("t_span");
          if (all.contains("t_end")) throw py::type_error("simulate(): give t_span or t_end, not both");
          const std::vector<double> ends = DoublesOf(span, "t_span");
          if (ends.size() != 2) throw InputError("t_span", "must be (t_start, t_end), got " + Repr(span));
          t_start = ends[0];
          all["t_end"] = ends[1];
        }
        std::vector<double> t_eval;
        if (all.contains("t_eval")) {
          const py::object times = all.attr("pop")("t_eval");
          if (all.contains("sample_dt")) throw py::type_error("simulate(): give t_eval or sample_dt, not both");
          t_eval = DoublesOf(times, "t_eval");
          all["sample_dt"] = 0.0;  // no grid: the samples are t_eval's (the summary's settings say so)
        }
        const SettingPatch keywords = KeywordPatch(SimulateSettings(), "simulate", all);
        const Configured<SimulationRequest> request = SimulateSettings().Resolve({&keywords});
        SimulateOptions options = request.options.options;
        options.sample_times = std::move(t_eval);
        options.t_start = t_start;
        options.Validate(FieldNames().Set("sample_times", "t_eval").Set("t_start", "t_span"));
        const SimulationPlan plan = PlanSimulation(model, request);
        const int n = model.dofs();
        std::vector<report::Sample> samples;
        std::vector<ContactEvent> impacts;
        SimulationObserver obs;
        obs.on_sample = [&](double t, const Eigen::VectorXd& z) { samples.push_back(report::SampleOf(model, t, z)); };
        obs.on_impact = [&](const ContactEvent& ev) {
          impacts.push_back(ev);
          if (on_impact.is_none()) return;
          py::gil_scoped_acquire acquire;
          on_impact(ev.t, ev.before, ev.after);
        };
        if (!progress.is_none()) {
          const double t_end = request.options.options.t_end;
          obs.on_progress = [&progress, t_end](double t) {
            py::gil_scoped_acquire acquire;
            progress(t, t_end);
          };
        }
        const SimulationSummary s = Interruptible([&] { return RunSimulation(model, plan, options, obs); });
        py::dict d = ToPython(report::SimulationJson(s, request));
        if (plan.truncation) d["truncation"] = ToPython(report::TruncationJson(*plan.truncation, plan.initial_energy));
        d["trajectory"] = TableDict(report::TrajectoryColumns(n), Pointers(samples));
        d["impact_log"] = TableDict(report::ImpactColumns(n), Pointers(impacts));
        return d;
      },
      py::arg("model"),
      Signed(TextSignature("simulate", "model, x0=None, v0=None", {"x0", "v0"},
                           "on_impact=None, progress=None, t_span=None, t_eval=None", SimulateSettings(), "simulate"),
             simulate_doc));

  static const std::string validate_doc =
      R"doc(Validate the potential 1- and/or 2-ipp orbits of a grid by long simulations.
period: (from, to, step), "FROM:TO:STEP" or one value.

Returns {"rows": arrays keyed as validation.csv, one per orbit and
integrator, "summary": the dict of validate's summary.json, with "passed"
and the settings blocks}. A quantity that does not apply to a row is NaN in
its float column (an empty CSV field: "impact_time_error" when the first
period did not have the predicted number of impacts, "t2" for one impact,
the manifold and perturbation columns of orbits not run that way), None in
the summary; no value is ever inf or NaN.)doc" + KeywordDoc(ValidateSettings(), "validate");
  mod.def(
      "validate",
      [](const Model& model, const py::args& args, const py::kwargs& kwargs) {
        py::dict all = kwargs.attr("copy")();  // the caller's dict is left as it was
        const py::object progress = all.contains("progress") ? all.attr("pop")("progress") : py::none();
        if (args.size() > 1) throw py::type_error("validate() takes at most 2 positional arguments (model, period)");
        if (args.size() == 1) {
          if (all.contains("period")) throw py::type_error("validate() got multiple values for argument 'period'");
          all["period"] = args[0];
        }
        // A period given as a number or (from, to, step): the grid's text, which
        // reads back exactly (FormatValue: 17 significant digits).
        const SettingPatch keywords = KeywordPatch(
            ValidateSettings(), "validate", all, [](const std::string& keyword, py::handle h) -> std::optional<SettingValue> {
              if (keyword != "period" || py::isinstance<py::str>(h)) return std::nullopt;
              const PeriodGrid g = GridOf(py::reinterpret_borrow<py::object>(h));
              return FormatValue(g.from) + ":" + FormatValue(g.to) + ":" + FormatValue(g.step);
            });
        const Configured<ValidationRequest> request = ValidateSettings().Resolve({&keywords});
        const AnalysisBasis b(model);
        const ValidationPlan plan = PlanValidation(b, request);
        // Made here, with the GIL (it checks and copies a Python object).
        const std::function<void(long, long)> report = ProgressOf(progress);
        const GridValidation v = Interruptible([&] { return RunValidation(model, b, plan, report, request.names); });
        py::dict d;
        d["rows"] = TableDict(report::ValidationColumns(), Pointers(v.results));
        d["summary"] = ToPython(report::ValidationJson(v.report, v.results, request));
        return d;
      },
      py::arg("model"),
      Signed(TextSignature("validate", "model, period=None", {"period"}, "progress=None", ValidateSettings(), "validate"),
             validate_doc));

  mod.def(
      "settings", [] { return ToPython(report::SettingsReferenceJson()); },
      Signed("settings()", R"doc(Every setting of simulate and validate, as `nsmodal settings --json` prints
them: a list of dicts with the keys name, scene_key, flag, python, kind,
default, unit, doc and commands.)doc"));

  mod.def(
      "load_settings",
      [](const std::string& path) {
        const Scene scene = LoadScene(path, "path");
        py::dict out;
        auto keywords = [](const auto& table, const SettingPatch& patch) {
          py::dict d;
          for (const auto& [name, given] : patch) d[py::str(table.Find(name)->info.python)] = ToPython(report::SettingValueJson(given.value));
          return d;
        };
        out["simulate"] = keywords(SimulateSettings(), scene.simulate);
        out["validate"] = keywords(ValidateSettings(), scene.validate);
        return out;
      },
      py::arg("path"),
      Signed("load_settings(path)", R"doc(The settings a scene file's [simulate] and [validate] tables give, as keyword
dicts: simulate(model, **load_settings(path)["simulate"]).)doc"));

  mod.def(
      "response",
      [](const Model& model, Integer<"impacts"> impacts, Integer<"periods"> periods, const py::object& frequency,
         const py::object& amplitude, bool backbone, Integer<"validate"> validate,
         const std::vector<std::string>& integrators, Integer<"threads"> threads, const py::object& sequence) {
        CheckThreads(threads, "threads");
        const ResponseOptions opt = ResponseOptionsOf(model, impacts, periods, frequency, amplitude, sequence);
        const std::optional<std::string> no_backbone = NoBackbone(model, opt);
        const FieldNames names = FieldNames().Set("periods", "validate");
        const ValidateOptions vopt = ResponseValidateOptions(validate, integrators, threads, names);
        ResponseLevels r;
        std::optional<BackboneMatch> match;
        std::optional<ResponseValidation> v;
        Interruptible([&] {
          r = ComputeResponseLevels(model, opt, {opt.fixed});
          if (backbone && opt.parameter == ResponseParameter::kFrequency) {
            if (no_backbone) {
              r.notes.push_back("no backbone: " + *no_backbone);
            } else {
              match = MatchBackbone(model, opt, r.points);
            }
          }
          if (validate > 0) v = ValidateResponse(model, r.rows, vopt, {}, names);
        });
        py::dict d;
        if (v) d["validation"] = TableDict(report::ForcedValidationColumns(), Pointers(v->rows));
        d["rows"] = TableDict(report::ResponseColumns(model.dofs()), Pointers(r.rows));
        d["points"] = TableDict(report::ResponsePointColumns(), Pointers(r.points));
        d["branch_ends"] = r.ends;
        d["notes"] = r.notes;
        if (match) {
          std::vector<const OrbitRecord*> records;
          for (const auto& list : match->backbone.at) {
            for (const OrbitRecord& rec : list) records.push_back(&rec);
          }
          d["backbone"] = TableDict(report::BackboneColumns(MakeModalBasis(model)), records);
          // The nonsmooth mode's frequency at each peak's energy (NaN: none).
          std::vector<double> mode_w;
          for (const std::optional<double>& w : match->mode_frequency) mode_w.push_back(w ? *w : kNaN);
          d["points"]["mode_w"] = py::array_t<double>(static_cast<py::ssize_t>(mode_w.size()), mode_w.data());
        }
        return d;
      },
      py::arg("model"), py::arg("impacts") = 1, py::arg("periods") = 1, py::arg("frequency") = py::none(),
      py::arg("amplitude") = py::none(), py::arg("backbone") = true, py::arg("validate") = 0,
      py::arg("integrators") = std::vector<std::string>{"exact"}, py::arg("threads") = 0,
      py::arg("sequence") = py::none(),
      Signed("response(model, impacts=1, periods=1, frequency=None, amplitude=None, backbone=True, validate=0, integrators=['exact'], threads=0, sequence=None)", R"doc(Forced, damped response curves: the (m, n) = (impacts, periods) families of
periodic orbits followed through the forcing frequency or amplitude by
pseudo-arclength continuation (folds passed), with their stability.
sequence=[1, 2] (contact numbers, up to 8): the contact struck by each impact
(impacts is then its length); None: every impact on contact 1.

One of frequency and amplitude is a grid (from, to, step) or 'FROM:TO:STEP',
the other one value (None: the model's forcing; amplitude is max |f_i|, the
model's forcing_amplitude giving the direction). impacts = 0: the linear,
non-impacting response in closed form. Needs damping or e < 1.

Returns {"rows": arrays keyed as response.csv (w, amplitude, period, impacts,
energy, max_xc, impact_velocity, admissible, stable, max_multiplier, t_impact,
x1.., v1.., branch, periods, residual), "points": arrays keyed as
response_points.csv (w, amplitude, kind in fold | period-doubling | grazing |
zero-velocity | peak | torus, energy, ...; with "mode_w", the nonsmooth mode's
frequency at a peak's energy, to compare with w / periods, when a backbone
is computed), "branch_ends",
"notes", and for a frequency sweep with backbone=True "backbone": arrays
keyed as backbone.csv (the conservative twin's 1-ipp mode, w = 2 pi / T, over
the grid's frequencies divided by periods; none, with a note, for a sequence
over several contacts or a model with a rigid-body mode).
validate > 0: every point simulated that many periods with each of
`integrators`; "validation": arrays keyed as response_validation.csv (the
verdicts of validate: consistent, reason, deviation_end, measured_growth...).)doc"));

  mod.def(
      "continue_parameter",
      [](const Model& model, const std::string& parameter, const py::object& range, Integer<"impacts"> impacts,
         Integer<"periods"> periods, const py::object& sequence, const py::object& period) {
        if (!model.forcing.HasHarmonic()) {
          // A free model: its 1-impact family's transitions in the parameter.
          if (period.is_none()) {
            throw InputError("period", "is needed for a model with no harmonic force: the free 1-impact family's "
                                       "period grid (from, to, step), whose transitions are followed");
          }
          for (const auto& [given, argument] : {std::pair{static_cast<int>(impacts) != 1, "impacts"},
                                                std::pair{static_cast<int>(periods) != 1, "periods"},
                                                std::pair{!sequence.is_none(), "sequence"}}) {
            if (given) {
              throw InputError(argument, "is for a forced model; a model with no harmonic force follows its free "
                                         "1-impact family (period=...)");
            }
          }
          const ModelParameter p = ParseModelParameter(model, parameter, "parameter");
          const PeriodGrid values = ParseParameterRange(RangeText(range, "range"), "range");
          const PeriodGrid grid = GridOf(period);
          CheckFamilyRequest(model, p, values, grid);
          FamilyContinuation f;
          Interruptible([&] { f = FollowFamily(model, p, values, grid); });
          py::dict d;
          d["transitions"] = TableDict(report::FamilyColumns(parameter), Pointers(f.rows));
          d["notes"] = f.notes;
          return d;
        }
        if (!period.is_none()) {
          throw InputError("period", "is for a model with no harmonic force (the free family's periods), got " +
                                         Repr(period));
        }
        const ResponseRequest request = MakeContinuationRequest(model, parameter, RangeText(range, "range"), impacts,
                                                                periods, FieldNames(), SequenceText(sequence));
        ResponseLevels r;
        Interruptible([&] { r = ComputeResponseLevels(model, request.options, request.levels); });
        py::dict d;
        d["rows"] = TableDict(report::ContinuationColumns(model.dofs(), parameter), Pointers(r.rows));
        d["points"] = TableDict(report::ContinuationPointColumns(parameter), Pointers(r.points));
        d["branch_ends"] = r.ends;
        d["notes"] = r.notes;
        return d;
      },
      py::arg("model"), py::arg("parameter"), py::arg("range"), py::arg("impacts") = 1, py::arg("periods") = 1,
      py::arg("sequence") = py::none(), py::arg("period") = py::none(),
      Signed("continue_parameter(model, parameter, range, impacts=1, periods=1, sequence=None, period=None)", R"doc(A forced response followed in one parameter of the model, the others held:
parameter by its scene key, 'gap', 'restitution', 'contact[2].gap',
'masses[1]', 'springs[2]', 'damping_ratios[1]', 'rayleigh_damping[2]',
'amplitude' (max |f_i|, the force's shape kept) or 'frequency'; range
(from, to), (from, to, step) or 'FROM:TO[:STEP]' (step: the largest step and
the spacing of the values solved at fixed parameter; default (to - from) /
300). The model is rebuilt at each value from its keywords (a mass or spring
changes its modal damping as the keywords would); a range that leaves the
valid model (a negative mass, e > 1) is refused naming the field. Folds,
period doublings, torus points, grazings, zero-velocity impacts and peaks
are located on the branches.

Returns {"rows": arrays keyed as continuation.csv (the parameter's column,
named as given, then response.csv's), "points": arrays keyed as
continuation_points.csv (the parameter, then response_points.csv's),
"branch_ends", "notes"}.

A model with no harmonic force: its free (e = 1) 1-impact family's
transitions and stability changes over the period grid `period` followed in
a mass, a spring or a gap (the gap only rescales: computed once); returns
{"transitions": arrays keyed as continue's transitions.csv (the parameter,
T, kind, energy, contact, track), "notes"}.)doc"));

  mod.def(
      "follow_curve",
      [](const Model& model, const std::string& parameter, const py::object& range, const std::string& second,
         const py::object& second_range, const std::string& follow, Integer<"impacts"> impacts,
         Integer<"periods"> periods, const py::object& sequence) {
        const CurveOptions o =
            MakeCurveRequest(model, parameter, RangeText(range, "range"), second, RangeText(second_range, "second_range"),
                             follow, impacts, periods, FieldNames(), SequenceText(sequence));
        CurveSet set;
        Interruptible([&] { set = FollowCurves(model, o); });
        py::dict d;
        d["rows"] = TableDict(report::CurveColumns(model.dofs(), parameter, second), Pointers(set.rows));
        d["curve_ends"] = set.ends;
        d["notes"] = set.notes;
        return d;
      },
      py::arg("model"), py::arg("parameter"), py::arg("range"), py::arg("second"), py::arg("second_range"),
      py::arg("follow"), py::arg("impacts") = 1, py::arg("periods") = 1, py::arg("sequence") = py::none(),
      Signed("follow_curve(model, parameter, range, second, second_range, follow, impacts=1, periods=1, sequence=None)",
             R"doc(The curves of a special point of a forced response in two parameters of
the model (codimension two): follow 'fold', 'period-doubling' or 'grazing'
(impacts=0: the linear response touching the wall) over the window range x
second_range (each (from, to), (from, to, step) or 'FROM:TO[:STEP]';
parameters named as in continue_parameter). The curves start from the
special points of continuations in one parameter on three lines of each
parameter; the points where a curve meets another kind's curve (a fold, a
period doubling, a grazing, a zero-velocity impact) and a fold curve's
cusps are rows of their own, in order along the curve.

Returns {"rows": arrays keyed as curve.csv (both parameters' columns, kind,
the orbit's columns as response.csv's with curve for branch, condition: the
defining condition's value), "curve_ends", "notes"}.)doc"));

  mod.def(
      "with_parameter",
      [](const Model& model, const std::string& parameter, double value) {
        return WithParameter(model, ParseModelParameter(model, parameter, "parameter"), value);
      },
      py::arg("model"), py::arg("parameter"), py::arg("value"),
      Signed("with_parameter(model, parameter, value)", R"doc(The model with one parameter, named as in
continue_parameter ('gap', 'masses[1]', 'amplitude', ...), at `value`, checked
as a scene is (a ValueError naming the scene's field and the value).)doc"));

  mod.def(
      "_identify",
      [](const Model& model, const std::vector<int>& contacts, Integer<"periods"> periods,
         const std::vector<double>& times) {
        // The periodic orbit `response` would locate for a simulated
        // attractor: its sequence (contacts from 1) over n forcing periods,
        // solved from the simulated impact times (t from a stroboscopic
        // instant, a multiple of 2 pi / w: the forcing phase is w t).
        const double w = model.forcing.frequency, a = model.ForceAmplitude().cwiseAbs().maxCoeff();
        py::dict d;
        ForcedOrbit o;
        if (contacts.empty()) {
          o = LinearResponse(model, w, a);
        } else {
          std::vector<int> seq;
          for (int c : contacts) seq.push_back(c - 1);
          const ForcedProblem p(model, seq, periods, w, a);
          Eigen::VectorXd u = Eigen::VectorXd::Zero(p.unknowns());
          u[0] = std::fmod(w * times.front(), 2.0 * M_PI);
          for (std::size_t i = 1; i < times.size() && static_cast<int>(i) < p.impacts(); ++i) {
            u[static_cast<Eigen::Index>(i)] = times[i] - times[i - 1];
          }
          const std::optional<Eigen::VectorXd> solved = p.Solve(u);
          d["found"] = solved.has_value();
          if (!solved) return d;
          o = p.Orbit(*solved);
          // The largest distance of a located impact time from the nearest
          // simulated one, modulo a forcing period (the located orbit starts
          // in the first forcing period; the attractor's points are the same
          // set).
          double worst = 0.0;
          const double tf = 2.0 * M_PI / w;
          for (const double t : o.times) {
            double nearest = std::numeric_limits<double>::infinity();
            for (const double s : times) nearest = std::min(nearest, std::abs(std::remainder(t - s, tf)));
            worst = std::max(worst, nearest);
          }
          d["time_error"] = worst;
        }
        d["found"] = true;
        d["admissible"] = o.admissible;
        d["stable"] = o.stable;
        d["max_multiplier"] = o.max_multiplier;
        d["residual"] = o.residual;
        return d;
      },
      py::arg("model"), py::arg("contacts"), py::arg("periods"), py::arg("times"),
      "Internal (nsmodal.study): the analytic orbit of a simulated attractor (forced_orbit.h).");

  mod.def(
      "_parameter_value",
      [](const Model& model, const std::string& parameter) {
        return ParameterValue(model, ParseModelParameter(model, parameter, "parameter"));
      },
      py::arg("model"), py::arg("parameter"), "Internal (nsmodal.study): the model's own value of a parameter.");

  mod.def(
      "_contact_normal",
      [](const Model& model, Integer<"contact"> contact) {
        if (contact < 1 || contact > model.NumContacts()) {
          throw InputError("contact", "must be a contact of the model, 1 to " + std::to_string(model.NumContacts()) +
                                          ", got " + std::to_string(contact));
        }
        const Contact& c = model.contacts[static_cast<std::size_t>(contact - 1)];
        return py::make_tuple(Eigen::VectorXd(c.normal), c.gap);
      },
      py::arg("model"), py::arg("contact"),
      "Internal (nsmodal.study): contact `contact`'s (1-based) normal n and gap d (n . x <= d), as the model holds "
      "them.");
  mod.def(
      "_settle",
      [](const Model& model, const Eigen::MatrixXd& states, Integer<"periods"> periods, Integer<"window"> window,
         double tol, const std::optional<Eigen::VectorXd>& phases) {
        // The batch of nsmodal.study's chunks: one Settle per row (x, v),
        // started at its forcing phase (phases[k]; none: 0).
        const int n = model.dofs();
        if (states.cols() != 2 * n) {
          throw InputError("states", "must have 2N = " + std::to_string(2 * n) + " columns (x, v), got " +
                                         std::to_string(states.cols()));
        }
        if (phases && phases->size() != states.rows()) {
          throw InputError("phases", "must have one entry per state (" + std::to_string(states.rows()) + "), got " +
                                         std::to_string(phases->size()));
        }
        SettleOptions o;
        o.periods = periods;
        o.window = window;
        o.tol = tol;
        o.Validate();
        for (Eigen::Index k = 0; phases && k < phases->size(); ++k) {
          o.phase = (*phases)[k];
          o.Validate();
        }
        const Eigen::Index rows = states.rows();
        Eigen::MatrixXd out = Eigen::MatrixXd::Constant(rows, 2 * n, std::numeric_limits<double>::quiet_NaN());
        Eigen::VectorXi period = Eigen::VectorXi::Zero(rows);
        Eigen::VectorXd repetition(rows);
        std::vector<bool> rough(static_cast<std::size_t>(rows));
        std::vector<std::vector<double>> times(static_cast<std::size_t>(rows));
        std::vector<std::vector<int>> contacts(static_cast<std::size_t>(rows));
        std::vector<std::vector<double>> velocities(static_cast<std::size_t>(rows));
        std::vector<std::string> messages(static_cast<std::size_t>(rows));
        Interruptible([&] {
          for (Eigen::Index k = 0; k < rows; ++k) {
            const Eigen::VectorXd z = states.row(k).transpose();
            const std::size_t i = static_cast<std::size_t>(k);
            Settled r;
            SettleOptions ok = o;
            ok.phase = phases ? (*phases)[k] : 0.0;
            try {
              r = Settle(model, z.head(n), z.tail(n), ok);
            } catch (const InputError& e) {
              // A start beyond a wall is no motion: period -1, said why.
              if (e.field() != "simulate.initial_position") throw;
              period[k] = -1;
              messages[i] = e.what();
              continue;
            }
            if (r.settled) out.row(k) = r.state.transpose();
            period[k] = r.period;
            repetition[k] = r.repetition;
            rough[i] = r.zeno_or_sticking;
            times[i] = r.impact_times;
            velocities[i] = r.impact_velocities;
            for (int c : r.impact_contacts) contacts[i].push_back(c + 1);
            messages[i] = r.message;
          }
        });
        py::dict d;
        d["period"] = period;
        d["state"] = out;
        d["repetition"] = repetition;
        d["zeno_or_sticking"] = rough;
        d["impact_times"] = times;
        d["impact_contacts"] = contacts;
        d["impact_velocities"] = velocities;
        d["message"] = messages;
        return d;
      },
      py::arg("model"), py::arg("states"), py::arg("periods"), py::arg("window") = 32, py::arg("tol") = 1e-6,
      py::arg("phases") = py::none(),
      "Internal (nsmodal.study): where each initial state (a row x, v), started at its forcing phase "
      "(phases, rad; none: 0), settles (settle.h); period 0: not settled, -1: a start beyond a wall.");

  mod.attr("__version__") = NSMODAL_VERSION;
}
