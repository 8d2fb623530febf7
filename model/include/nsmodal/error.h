#pragma once
// Errors of user input. Three tiers, as in Drake: internal invariants abort
// (assert), bad user input throws InputError naming the field and the value,
// numerical outcomes are returned as a status in the result structs.
#include <stdexcept>
#include <string>

namespace nsmodal {

class InputError : public std::runtime_error {
 public:
  InputError(const std::string& field, const std::string& message)
      : std::runtime_error(field + ": " + message), field_(field) {}
  const std::string& field() const { return field_; }

 private:
  std::string field_;
};

}  // namespace nsmodal
