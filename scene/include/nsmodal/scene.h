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
//   # damping, at most one of (none: C = 0):
//   rayleigh_damping = [0.0, 0.01]  # C = a M + b K
//   damping_ratios = [0.01, 0.02]   # modal damping, one ratio per linear mode
//   damping_matrix = [[...]]        # any symmetric positive semi-definite C
//
//   [forcing]                  # optional: f0 + f cos(w t) on the dofs
//   amplitude = [0.05, 0.0]    # f, length N (needs frequency)
//   frequency = 0.6            # w in rad/s
//   constant = [0.0, 0.0]      # f0, length N (preload, gravity)
//
//   [simulate]                 # optional; the simulate command's flags override it
//   initial_position = [0.0, 0.5]   # every key: `nsmodal settings`
//   integrator = "exact"
//
//   [validate]                 # optional; the validate command's flags override it
//   period = "2:20:0.5"        # every key: `nsmodal settings`
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "nsmodal/model.h"
#include "nsmodal/settings.h"

namespace nsmodal {

// A scene: the model, and the settings its [simulate] and [validate]
// tables give (settings.h: keys from simulate_settings.h's and
// validate_settings.h's tables, each value with the key it came from).
struct Scene {
  std::string source;  // file name, for messages
  Model model;
  SettingPatch simulate;
  SettingPatch validate;
  std::optional<BarSpec> bar;  // [system] bar: the model is this bar's (figures draw it in space and time)
};

// The largest scene file read: 16 MiB. A chain or a bar of kMaxDofs dofs is
// a few tens of kB; the bound is for dense matrices (mass_matrix and
// stiffness_matrix of N ~ 500 at 17 digits fill about 12 MB) and keeps a
// wrong path (a device, a log) from being read whole into memory.
inline constexpr std::size_t kMaxSceneBytes = std::size_t{16} << 20;

// The text of a scene file, read by the one bounded reader the CLI and the
// Python module share: only a regular file (a FIFO, a device or a directory
// is refused without blocking: it is opened O_NONBLOCK and checked with
// fstat), at most kMaxSceneBytes (at most that plus one byte is read), no
// NUL in the path (a C path would stop there and open another file).
// Throws InputError naming `field` and the path.
std::string ReadSceneFile(const std::string& path, const std::string& field = "scene");

// The example scenes of configs/, compiled in: {name, TOML text}, by name
// ("bar", "forced", "paper", "paper-simulate").
const std::vector<std::pair<std::string, std::string>>& BuiltinScenes();

// The scene at `path`, or, when no file is there and `path` is the name of
// a built-in scene ("paper"), that scene. Throws InputError naming the field
// ("scene", or `field`, for a file that cannot be read or parsed, with the
// parser's line and column; a missing file's message lists the built-in
// names).
Scene LoadScene(const std::string& path, const std::string& field = "scene");
Scene ParseScene(const std::string& toml_text, const std::string& source = "<string>");

}  // namespace nsmodal
