#pragma once
// Where each option's value came from, so that an error names what the user
// actually wrote: a flag ("--t-end"), a scene key ("simulate.t_end") or a
// Python keyword ("t_end"). Options structs validate with a FieldNames; a key
// that was not given a name of its own is named prefix + key.
#include <map>
#include <string>
#include <utility>

namespace nsmodal {

class FieldNames {
 public:
  explicit FieldNames(std::string prefix = "") : prefix_(std::move(prefix)) {}
  FieldNames& Set(const std::string& key, std::string name) {
    names_[key] = std::move(name);
    return *this;
  }
  std::string operator()(const std::string& key) const {
    const auto it = names_.find(key);
    return it != names_.end() ? it->second : prefix_ + key;
  }

 private:
  std::string prefix_;
  std::map<std::string, std::string> names_;
};

}  // namespace nsmodal
