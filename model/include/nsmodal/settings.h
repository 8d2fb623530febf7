#pragma once
// One declaration per setting (issue 23). A setting is declared once, in the
// table of the options struct it fills ({name, scene key, CLI flag, Python
// keyword, member, default, unit, doc, commands}); every face is made from
// that table:
//   the scene parser    reads [section] key = value by the scene key;
//   the CLI             adds --flag with its help (doc, unit, default) to each
//                       command the setting lists;
//   the Python module   takes the keyword, and writes its docstring;
//   the summaries       write the "settings" and "settings_source" blocks;
//   `nsmodal settings`  prints the table (--json: a list of objects), from
//                       which the docs' reference page is generated.
// The default is the member's value in the table's default-constructed
// options (the struct's own initialiser: one declaration of the default too).
//
// Every value remembers where it came from: the default, the scene, a flag
// or a Python keyword, and the name the user wrote for it ("--t-end",
// "simulate.t_end", "t_end"), so that a refusal names what the user wrote.
// Precedence: default < scene < flag or keyword.
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <variant>
#include <vector>

#include "nsmodal/field_names.h"

namespace nsmodal {

enum class SettingKind { kReal, kInteger, kText, kRealList, kIntegerList, kTextList };
std::string ToString(SettingKind kind);  // real, integer, text, real list, integer list, text list

// A value as the faces carry it. std::monostate: no value (a setting whose
// default is "not given", such as simulate's modes).
using SettingValue = std::variant<std::monostate, double, long, std::string, std::vector<double>, std::vector<long>,
                                  std::vector<std::string>>;

enum class SettingSource { kDefault, kScene, kFlag, kKeyword };
std::string ToString(SettingSource source);  // default, scene, flag, keyword

// A value for people and for TOML-like text: a real in the fewest digits that
// read back exactly, lists in brackets, text in quotes; "none"
// for no value.
std::string FormatSettingValue(const SettingValue& value);

struct SettingInfo {
  std::string name;       // the member, the JSON key: "t_end"
  SettingKind kind = SettingKind::kReal;
  std::string scene_key;  // the key in its scene table ("t_end" in [simulate]); empty: not in scenes
  std::string flag;       // "--t-end"; empty: no flag
  std::string python;     // the Python keyword ("t_end"); empty: not a keyword
  std::string unit;       // "s", "m", "rad/s"; empty: dimensionless or not a quantity
  std::string doc;        // one sentence, for --help, docstrings and the reference page
  std::vector<std::string> commands;  // the CLI commands (and Python functions) that take it
  bool Takes(const std::string& command) const;
};

// A value given by one face, with the name the user wrote for it.
struct GivenSetting {
  SettingValue value;
  std::string field;  // "--t-end", "simulate.t_end", "t_end"
  SettingSource source = SettingSource::kDefault;
};
using SettingPatch = std::map<std::string, GivenSetting>;  // by setting name

// Where a resolved value came from.
struct SettingOrigin {
  SettingSource source = SettingSource::kDefault;
  std::string field;  // as written; for a default, the scene key (section.key) or the name
};

// Throws std::logic_error: a face passed a setting its table does not declare.
[[noreturn]] void ThrowUnknownSetting(const std::string& section, const std::string& name);

template <class Options>
struct Setting {
  SettingInfo info;
  std::function<SettingValue(const Options&)> get;
  // Stores a value of the setting's kind; throws InputError naming `field`
  // for one the member cannot hold (an unknown integrator name).
  std::function<void(Options&, const SettingValue&, const std::string& field)> set;
  // The value's own range, if it has one (the options' Validate runs it):
  // throws InputError naming `field` and the value.
  std::function<void(const SettingValue&, const std::string& field)> check = {};
};

// Options resolved from the faces, with the origin of every setting and the
// FieldNames an options struct's Validate takes (each value named as written).
template <class Options>
struct Configured {
  Options options;
  std::map<std::string, SettingOrigin> origin;  // every setting of the table
  FieldNames names;
};

// A table: the settings of one options struct, in the order people read them.
// `section` is the scene table that holds them ("simulate", "validate").
template <class Options>
class SettingTable {
 public:
  SettingTable(std::string section, std::vector<Setting<Options>> settings, Options defaults = {})
      : section_(std::move(section)), settings_(std::move(settings)), defaults_(std::move(defaults)) {}

  const std::string& section() const { return section_; }
  const std::vector<Setting<Options>>& settings() const { return settings_; }
  const Options& defaults() const { return defaults_; }
  SettingValue Default(const Setting<Options>& s) const { return s.get(defaults_); }
  // "simulate.t_end"; empty when the setting is not in scenes.
  std::string SceneField(const SettingInfo& info) const {
    return info.scene_key.empty() ? std::string() : section_ + "." + info.scene_key;
  }
  const Setting<Options>* Find(const std::string& name) const {
    for (const Setting<Options>& s : settings_) {
      if (s.info.name == name) return &s;
    }
    return nullptr;
  }
  const Setting<Options>* FindSceneKey(const std::string& key) const {
    for (const Setting<Options>& s : settings_) {
      if (!s.info.scene_key.empty() && s.info.scene_key == key) return &s;
    }
    return nullptr;
  }
  const Setting<Options>* FindKeyword(const std::string& keyword) const {
    for (const Setting<Options>& s : settings_) {
      if (!s.info.python.empty() && s.info.python == keyword) return &s;
    }
    return nullptr;
  }

  // The defaults, then each patch in turn (the scene's, then the flags' or
  // the keywords'): a later patch overrides an earlier one. A patch naming a
  // setting the table lacks is an internal error (std::logic_error).
  Configured<Options> Resolve(const std::vector<const SettingPatch*>& patches) const {
    Configured<Options> c{defaults_, {}, FieldNames(section_ + ".")};
    for (const Setting<Options>& s : settings_) {
      const std::string scene = SceneField(s.info);
      c.origin[s.info.name] = {SettingSource::kDefault, scene.empty() ? s.info.name : scene};
    }
    for (const SettingPatch* patch : patches) {
      if (patch == nullptr) continue;
      for (const auto& [name, given] : *patch) {
        const Setting<Options>* s = Find(name);
        if (s == nullptr) ThrowUnknownSetting(section_, name);
        s->set(c.options, given.value, given.field);
        c.origin[name] = {given.source, given.field};
        c.names.Set(name, given.field);
      }
    }
    return c;
  }

 private:
  std::string section_;
  std::vector<Setting<Options>> settings_;
  Options defaults_;
};

// Settings of a struct that holds `Inner` as a member: each read and written
// through `member`; `keep` chooses which (by their info). Validation takes
// the integrator's tolerances this way, declared once in simulate's table.
template <class Outer, class Inner>
std::vector<Setting<Outer>> LiftSettings(const std::vector<Setting<Inner>>& settings, Inner Outer::*member,
                                         const std::function<bool(const SettingInfo&)>& keep) {
  std::vector<Setting<Outer>> out;
  for (const Setting<Inner>& s : settings) {
    if (!keep(s.info)) continue;
    out.push_back({s.info, [get = s.get, member](const Outer& o) { return get(o.*member); },
                   [set = s.set, member](Outer& o, const SettingValue& v, const std::string& field) {
                     set(o.*member, v, field);
                   }});
  }
  return out;
}

// Member accessors for the common kinds: the value converted to and from the
// variant. A value of another kind is an internal error (the faces convert by
// the setting's kind).
double RealOf(const SettingValue& v);
long IntegerOf(const SettingValue& v);
const std::string& TextOf(const SettingValue& v);
const std::vector<double>& RealListOf(const SettingValue& v);
const std::vector<long>& IntegerListOf(const SettingValue& v);
const std::vector<std::string>& TextListOf(const SettingValue& v);

template <class Options>
Setting<Options> RealSetting(SettingInfo info, double Options::*member) {
  info.kind = SettingKind::kReal;
  return {std::move(info), [member](const Options& o) -> SettingValue { return o.*member; },
          [member](Options& o, const SettingValue& v, const std::string&) { o.*member = RealOf(v); }};
}
// An integer setting's value: a long, or a real that is a whole number (the
// CLI reads integer flags as reals, so that 1.5 is refused here, naming the
// flag, as every other bad value is). Throws InputError naming `field` for a
// fraction, a non-finite value, or one outside [lo, hi] (an int member given
// a long: the conversion would wrap).
long WholeNumberOf(const SettingValue& v, long lo, long hi, const std::string& field);

template <class Options, class Int>
Setting<Options> IntegerSetting(SettingInfo info, Int Options::*member) {
  info.kind = SettingKind::kInteger;
  return {std::move(info), [member](const Options& o) -> SettingValue { return static_cast<long>(o.*member); },
          [member](Options& o, const SettingValue& v, const std::string& field) {
            o.*member = static_cast<Int>(WholeNumberOf(v, static_cast<long>(std::numeric_limits<Int>::min()),
                                                       static_cast<long>(std::numeric_limits<Int>::max()), field));
          }};
}
template <class Options>
Setting<Options> TextSetting(SettingInfo info, std::string Options::*member) {
  info.kind = SettingKind::kText;
  return {std::move(info), [member](const Options& o) -> SettingValue { return o.*member; },
          [member](Options& o, const SettingValue& v, const std::string&) { o.*member = TextOf(v); }};
}

template <class Options>
Setting<Options> RealListSetting(SettingInfo info, std::vector<double> Options::*member) {
  info.kind = SettingKind::kRealList;
  return {std::move(info), [member](const Options& o) -> SettingValue { return o.*member; },
          [member](Options& o, const SettingValue& v, const std::string&) { o.*member = RealListOf(v); }};
}

}  // namespace nsmodal
