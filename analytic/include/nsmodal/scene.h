#pragma once
// A scene is a TOML file (configs/*.toml). Its key names are a contract:
//
//   [system]
//   masses = [1.0, 1.0]        # a chain: masses, and springs ground-m1, m1-m2, ...
//   springs = [0.85, 2.0]
//   # or: mass_matrix = [[...]], stiffness_matrix = [[...]] (symmetric positive definite)
//   contact_dof = 2            # 1-based; default: the last dof
//   gap = 1.0                  # d
//   restitution = 1.0          # e
#include <string>

#include "nsmodal/model.h"

namespace nsmodal {

struct Scene {
  std::string source;  // file name, for messages
  Model model;
};

// Throws InputError naming the field ("scene" for a file that cannot be read
// or parsed, with the parser's line and column).
Scene LoadScene(const std::string& path);
Scene ParseScene(const std::string& toml_text, const std::string& source = "<string>");

}  // namespace nsmodal
