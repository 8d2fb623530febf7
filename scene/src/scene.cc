#include "nsmodal/scene.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>
#include <sstream>
#include <toml++/toml.h>

#include "nsmodal/error.h"
#include "nsmodal/model_spec.h"
#include "nsmodal/simulate_settings.h"
#include "nsmodal/validate_settings.h"

namespace nsmodal {
namespace {

double ReadNumber(const toml::node& node, const std::string& field) {
  if (auto v = node.as_floating_point()) return v->get();
  if (auto v = node.as_integer()) return static_cast<double>(v->get());
  std::ostringstream os;
  node.visit([&os](auto&& v) { os << v; });
  throw InputError(field, "must be a number, got " + os.str());
}

std::vector<double> ReadVector(const toml::node& node, const std::string& field) {
  const toml::array* arr = node.as_array();
  if (arr == nullptr) throw InputError(field, "must be an array of numbers");
  std::vector<double> out;
  for (std::size_t i = 0; i < arr->size(); ++i) {
    out.push_back(ReadNumber(*arr->get(i), field + "[" + std::to_string(i + 1) + "]"));
  }
  return out;
}

Eigen::MatrixXd ReadMatrix(const toml::node& node, const std::string& field) {
  const toml::array* rows = node.as_array();
  if (rows == nullptr || rows->empty()) throw InputError(field, "must be a non-empty array of rows");
  const int n = static_cast<int>(rows->size());
  Eigen::MatrixXd m(n, n);
  for (int i = 0; i < n; ++i) {
    const std::string row_field = field + "[" + std::to_string(i + 1) + "]";
    std::vector<double> row = ReadVector(*rows->get(i), row_field);
    if (static_cast<int>(row.size()) != n) {
      throw InputError(row_field, "must have " + std::to_string(n) + " entries (a square matrix), got " +
                                      std::to_string(row.size()));
    }
    for (int j = 0; j < n; ++j) m(i, j) = row[j];
  }
  return m;
}

// [forcing]: f0 + f cos(w t), each key as given (AssembleModel pairs them).
void ReadForcing(const toml::node& node, ModelSpec& spec) {
  const toml::table* table = node.as_table();
  if (table == nullptr) throw InputError("forcing", "must be a table");
  for (auto&& [key, value] : *table) {
    const std::string k(key.str());
    const std::string field = "forcing." + k;
    if (k == "amplitude") {
      spec.forcing_amplitude = ReadVector(value, field);
    } else if (k == "constant") {
      spec.forcing_constant = ReadVector(value, field);
    } else if (k == "frequency") {
      spec.forcing_frequency = ReadNumber(value, field);
    } else {
      throw InputError(field, "is not a known key");
    }
  }
}

// [system] bar = { length, youngs_modulus, density, area, elements,
// boundary = "fixed-free" | "free-free", mass = "consistent" | "lumped" }.
BarSpec ReadBar(const toml::node& node) {
  const toml::table* t = node.as_table();
  if (t == nullptr) throw InputError("system.bar", "must be a table { length, youngs_modulus, density, area, elements }");
  BarSpec bar;
  for (auto&& [key, value] : *t) {
    const std::string k(key.str()), field = "system.bar." + k;
    if (k == "length") {
      bar.length = ReadNumber(value, field);
    } else if (k == "youngs_modulus") {
      bar.youngs_modulus = ReadNumber(value, field);
    } else if (k == "density") {
      bar.density = ReadNumber(value, field);
    } else if (k == "area") {
      bar.area = ReadNumber(value, field);
    } else if (k == "elements") {
      const double e = ReadNumber(value, field);
      // Range first: casting a non-finite or huge value to an integer is undefined.
      if (!(e >= 1 && e <= kMaxDofs) || e != std::floor(e)) {
        throw InputError(field, "must be an integer between 1 and " + std::to_string(kMaxDofs) + ", got " +
                                    FormatValue(e));
      }
      bar.elements = static_cast<int>(e);
    } else if (k == "boundary" || k == "mass") {
      const std::optional<std::string> text = value.value<std::string>();
      if (!text) throw InputError(field, "must be a string, got a non-string value");
      if (k == "boundary") {
        bar.boundary = ParseBarBoundary(*text, field);
      } else {
        bar.mass = ParseBarMass(*text, field);
      }
    } else {
      throw InputError(field, "is not a known key (length, youngs_modulus, density, area, elements, boundary, mass)");
    }
  }
  for (const char* required : {"length", "youngs_modulus", "density", "area", "elements"}) {
    if (!t->contains(required)) throw InputError(std::string("system.bar.") + required, "is missing");
  }
  return bar;
}

// A whole number of a list or a setting (the range is the options' to check).
long ReadInteger(const toml::node& node, const std::string& field) {
  const double x = ReadNumber(node, field);
  // Range first: casting a non-finite or huge value to an integer is undefined.
  if (!(std::abs(x) <= 9.007199254740992e15) || x != std::floor(x)) {
    throw InputError(field, "must be an integer, got " + FormatValue(x));
  }
  return static_cast<long>(x);
}

std::string ReadText(const toml::node& node, const std::string& field) {
  const auto* str = node.as_string();
  if (str == nullptr) throw InputError(field, "must be a string");
  return str->get();
}

const toml::array& ReadArray(const toml::node& node, const std::string& field) {
  const toml::array* arr = node.as_array();
  if (arr == nullptr) throw InputError(field, "must be an array");
  return *arr;
}

// A value of the setting's kind.
SettingValue ReadSetting(const toml::node& node, SettingKind kind, const std::string& field) {
  switch (kind) {
    case SettingKind::kReal: return ReadNumber(node, field);
    case SettingKind::kInteger: return ReadInteger(node, field);
    case SettingKind::kText: return ReadText(node, field);
    case SettingKind::kRealList: return ReadVector(node, field);
    case SettingKind::kIntegerList: {
      std::vector<long> out;
      const toml::array& arr = ReadArray(node, field);
      for (std::size_t i = 0; i < arr.size(); ++i) out.push_back(ReadInteger(*arr.get(i), field + "[" + std::to_string(i + 1) + "]"));
      return out;
    }
    case SettingKind::kTextList: {
      std::vector<std::string> out;
      const toml::array& arr = ReadArray(node, field);
      for (std::size_t i = 0; i < arr.size(); ++i) out.push_back(ReadText(*arr.get(i), field + "[" + std::to_string(i + 1) + "]"));
      return out;
    }
  }
  throw InputError(field, "has a kind no reader knows");
}

// [[contact]]: an array of tables, contact j (from 1) each, its keys as
// given (AssembleModel checks the forms and names contact[j].<key>).
std::vector<ContactSpec> ReadContacts(const toml::node& node) {
  const toml::array* arr = node.as_array();
  if (arr == nullptr) throw InputError("contact", "must be an array of tables: write each contact as [[contact]]");
  std::vector<ContactSpec> out;
  for (std::size_t j = 0; j < arr->size(); ++j) {
    const std::string at = "contact[" + std::to_string(j + 1) + "]";
    const toml::table* t = arr->get(j)->as_table();
    if (t == nullptr) throw InputError(at, "must be a table ([[contact]])");
    ContactSpec c;
    for (auto&& [key, value] : *t) {
      const std::string k(key.str()), field = at + "." + k;
      if (k == "dof") {
        c.dof = ReadNumber(value, field);
      } else if (k == "side") {
        c.side = ReadText(value, field);
      } else if (k == "between") {
        c.between = ReadVector(value, field);
      } else if (k == "normal") {
        c.normal = ReadVector(value, field);
      } else if (k == "gap") {
        c.gap = ReadNumber(value, field);
      } else if (k == "restitution") {
        c.restitution = ReadNumber(value, field);
      } else {
        throw InputError(field, "is not a known key (dof, side, between, normal, gap, restitution)");
      }
    }
    out.push_back(std::move(c));
  }
  return out;
}

// A settings table ([simulate], [validate]) by its keys (settings.h): each
// value of its setting's kind, named by its scene key.
template <class Options>
SettingPatch ReadSettings(const toml::node& node, const SettingTable<Options>& settings) {
  const toml::table* table = node.as_table();
  if (table == nullptr) throw InputError(settings.section(), "must be a table");
  SettingPatch patch;
  for (auto&& [key, value] : *table) {
    const std::string k(key.str());
    const std::string field = settings.section() + "." + k;
    const Setting<Options>* s = settings.FindSceneKey(k);
    if (s == nullptr) throw InputError(field, "is not a known key (`nsmodal settings` lists them)");
    patch[s->info.name] = {ReadSetting(value, s->info.kind, field), field, SettingSource::kScene};
  }
  return patch;
}

}  // namespace

Scene ParseScene(const std::string& toml_text, const std::string& source) {
  toml::table root;
  try {
    root = toml::parse(toml_text, source);
  } catch (const toml::parse_error& err) {
    std::ostringstream os;
    os << source << ":" << err.source().begin.line << ":" << err.source().begin.column << ": "
       << err.description();
    throw InputError("scene", os.str());
  }
  const toml::table* sys = root["system"].as_table();
  if (sys == nullptr) throw InputError("system", "the scene has no [system] table");
  for (auto&& [key, value] : *sys) {
    static const char* kKnown[] = {"masses",      "springs",          "mass_matrix",    "stiffness_matrix",
                                   "contact_dof", "gap",              "restitution",    "rayleigh_damping",
                                   "damping_ratios", "damping_matrix", "bar"};
    bool known = false;
    for (const char* k : kKnown) known = known || key.str() == k;
    if (!known) throw InputError("system." + std::string(key.str()), "is not a known key");
  }
  // Each key as given; AssembleModel builds the model (the faces' one rule).
  ModelSpec spec;
  auto given = [sys](const char* key, auto read) {
    using T = decltype(read(*sys, std::string()));
    const toml::node* n = sys->get(key);
    return n ? std::optional<T>(read(*n, std::string("system.") + key)) : std::optional<T>();
  };
  if (const toml::node* n = sys->get("bar")) spec.bar = ReadBar(*n);
  spec.masses = given("masses", ReadVector);
  spec.springs = given("springs", ReadVector);
  spec.mass_matrix = given("mass_matrix", ReadMatrix);
  spec.stiffness_matrix = given("stiffness_matrix", ReadMatrix);
  spec.contact_dof = given("contact_dof", ReadNumber);
  spec.gap = given("gap", ReadNumber);
  spec.restitution = given("restitution", ReadNumber);
  spec.rayleigh_damping = given("rayleigh_damping", ReadVector);
  spec.damping_ratios = given("damping_ratios", ReadVector);
  spec.damping_matrix = given("damping_matrix", ReadMatrix);
  if (const toml::node* node = root.get("forcing")) ReadForcing(*node, spec);
  if (const toml::node* node = root.get("contact")) spec.contacts = ReadContacts(*node);
  const Model model = AssembleModel(spec, FieldNames("system.")
                                              .Set("contact", "contact")
                                              .Set("form", "system")
                                              .Set("damping", "system")
                                              .Set("forcing.amplitude", "forcing.amplitude")
                                              .Set("forcing.frequency", "forcing.frequency"));
  Scene scene{source, model, {}, {}, spec.bar};
  if (const toml::node* node = root.get("simulate")) scene.simulate = ReadSettings(*node, SimulateSettings());
  if (const toml::node* node = root.get("validate")) scene.validate = ReadSettings(*node, ValidateSettings());
  for (auto&& [key, value] : root) {
    if (key.str() != "system" && key.str() != "simulate" && key.str() != "validate" && key.str() != "forcing" &&
        key.str() != "contact") {
      throw InputError(std::string(key.str()), "is not a known table");
    }
  }
  return scene;
}

namespace {

// The path as it can be shown: control characters (NUL included) escaped.
std::string Printable(const std::string& path) {
  std::string out;
  for (unsigned char ch : path) {
    if (ch < 0x20 || ch == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", ch);
      out += buf;
    } else {
      out += static_cast<char>(ch);
    }
  }
  return out;
}

const char* KindOf(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

struct Fd {
  int fd;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

std::string ReadSceneFile(const std::string& path, const std::string& field) {
  // (appended, not `+`: GCC 12 warns falsely on a chain of + here, -Wrestrict)
  std::string shown = "'";
  shown.append(Printable(path)).append("'");
  if (path.empty()) throw InputError(field, "is empty: give the path of a scene file");
  if (path.find('\0') != std::string::npos) throw InputError(field, shown + " holds a NUL character");
  // O_NONBLOCK: opening a FIFO with no writer would otherwise wait for one.
  const Fd f{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY)};
  if (f.fd < 0) throw InputError(field, "cannot open file " + shown + ": " + std::strerror(errno));
  struct stat st {};
  if (::fstat(f.fd, &st) != 0) throw InputError(field, "cannot stat " + shown + ": " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) {
    throw InputError(field, shown + " is " + KindOf(st.st_mode) + ": a scene is a regular file");
  }
  const std::string limit = "a scene file holds at most " + std::to_string(kMaxSceneBytes) + " bytes (16 MiB)";
  if (static_cast<unsigned long long>(st.st_size) > kMaxSceneBytes) {
    throw InputError(field, shown + " is " + std::to_string(st.st_size) + " bytes: " + limit);
  }
  // At most limit + 1 bytes: a file that grew past the limit since fstat is
  // refused too, not read whole.
  std::string text(static_cast<std::size_t>(st.st_size) + 1, '\0');
  std::size_t got = 0;
  while (got < kMaxSceneBytes + 1) {
    if (got == text.size()) text.resize(std::min(kMaxSceneBytes + 1, 2 * text.size()));
    const ssize_t r = ::read(f.fd, text.data() + got, text.size() - got);
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) throw InputError(field, "cannot read " + shown + ": " + std::strerror(errno));
    if (r == 0) break;
    got += static_cast<std::size_t>(r);
  }
  if (got > kMaxSceneBytes) throw InputError(field, shown + " grew past the limit while read: " + limit);
  text.resize(got);
  return text;
}

Scene LoadScene(const std::string& path, const std::string& field) {
  // A built-in name ("paper") when no regular file of that name is here: a
  // path with a slash never is a name; an empty path or one with a NUL gets
  // ReadSceneFile's own message.
  if (!path.empty() && path.find('/') == std::string::npos && path.find('\0') == std::string::npos) {
    struct stat st {};
    const int found = ::stat(path.c_str(), &st);
    const int error = errno;
    if (found != 0 || !S_ISREG(st.st_mode)) {
      for (const auto& [name, text] : BuiltinScenes()) {
        if (name == path) return ParseScene(text, "builtin:" + name);
      }
      if (found != 0 && error == ENOENT) {
        std::string names;
        for (const auto& [name, text] : BuiltinScenes()) names += (names.empty() ? "" : ", ") + name;
        throw InputError(field, "no file '" + Printable(path) + "', and no built-in scene of that name (" + names + ")");
      }
    }
  }
  return ParseScene(ReadSceneFile(path, field), path);
}

}  // namespace nsmodal
