#include "nsmodal/settings.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "nsmodal/error.h"
#include "nsmodal/model.h"

namespace nsmodal {

std::string ToString(SettingKind kind) {
  switch (kind) {
    case SettingKind::kReal: return "real";
    case SettingKind::kInteger: return "integer";
    case SettingKind::kText: return "text";
    case SettingKind::kRealList: return "real list";
    case SettingKind::kIntegerList: return "integer list";
    case SettingKind::kTextList: return "text list";
  }
  return "?";
}

std::string ToString(SettingSource source) {
  switch (source) {
    case SettingSource::kDefault: return "default";
    case SettingSource::kScene: return "scene";
    case SettingSource::kFlag: return "flag";
    case SettingSource::kKeyword: return "keyword";
  }
  return "?";
}

bool SettingInfo::Takes(const std::string& command) const {
  for (const std::string& c : commands) {
    if (c == command) return true;
  }
  return false;
}

namespace {

template <class T>
std::string ListText(const std::vector<T>& list, std::string (*one)(const T&)) {
  std::string out = "[";
  for (std::size_t i = 0; i < list.size(); ++i) out += (i ? ", " : "") + one(list[i]);
  return out + "]";
}
// The shortest text that reads back as v (1e-12, not 9.9999999999999998e-13).
std::string Real(const double& v) {
  char buf[32];
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}
std::string Integer(const long& v) { return std::to_string(v); }
std::string Text(const std::string& v) { return "\"" + v + "\""; }

template <class T>
const T& Get(const SettingValue& v, const char* kind) {
  if (const T* p = std::get_if<T>(&v)) return *p;
  throw std::logic_error(std::string("a setting's value is not a ") + kind);
}

}  // namespace

std::string FormatSettingValue(const SettingValue& value) {
  struct Visitor {
    std::string operator()(std::monostate) const { return "none"; }
    std::string operator()(double v) const { return Real(v); }
    std::string operator()(long v) const { return Integer(v); }
    std::string operator()(const std::string& v) const { return Text(v); }
    std::string operator()(const std::vector<double>& v) const { return ListText(v, &Real); }
    std::string operator()(const std::vector<long>& v) const { return ListText(v, &Integer); }
    std::string operator()(const std::vector<std::string>& v) const { return ListText(v, &Text); }
  };
  return std::visit(Visitor{}, value);
}

void ThrowUnknownSetting(const std::string& section, const std::string& name) {
  throw std::logic_error("the " + section + " settings declare no '" + name + "'");
}

long WholeNumberOf(const SettingValue& v, long lo, long hi, const std::string& field) {
  long x = 0;
  if (const double* d = std::get_if<double>(&v)) {
    // Range first: casting a non-finite or huge value to an integer is undefined.
    if (!std::isfinite(*d) || *d != std::floor(*d)) throw InputError(field, "must be a whole number, got " + FormatValue(*d));
    if (!(std::abs(*d) <= 9.007199254740992e15)) {
      throw InputError(field, FormatValue(*d) + " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    x = static_cast<long>(*d);
  } else {
    x = IntegerOf(v);
  }
  if (x < lo || x > hi) {
    throw InputError(field, std::to_string(x) + " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return x;
}

double RealOf(const SettingValue& v) { return Get<double>(v, "real"); }
long IntegerOf(const SettingValue& v) { return Get<long>(v, "integer"); }
const std::string& TextOf(const SettingValue& v) { return Get<std::string>(v, "text"); }
const std::vector<double>& RealListOf(const SettingValue& v) { return Get<std::vector<double>>(v, "real list"); }
const std::vector<long>& IntegerListOf(const SettingValue& v) { return Get<std::vector<long>>(v, "integer list"); }
const std::vector<std::string>& TextListOf(const SettingValue& v) {
  return Get<std::vector<std::string>>(v, "text list");
}

}  // namespace nsmodal
