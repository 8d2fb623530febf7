// One declaration per setting (settings.h, issue 23): every face made from
// the tables. Each test fails when a face lacks a setting: the scene parser
// (a key it does not read), the CLI (a flag a command lacks), the summaries
// (a setting missing from the settings blocks); the Python face is checked
// by python/tests/test_nsmodal.py from nsmodal.settings(). And provenance: a
// value given in a scene and overridden by a flag remembers both.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "command_line.h"
#include "nsmodal/error.h"
#include "nsmodal/json.h"
#include "nsmodal/scene.h"
#include "nsmodal/simulate_settings.h"
#include "nsmodal/validate_settings.h"

namespace nsmodal {
namespace {

const char* kSystem = "[system]\nmasses = [1.0, 1.0]\nsprings = [0.85, 2.0]\ngap = 1.0\nrestitution = 1.0\n";

// A value of the setting's kind that its checks accept, as TOML: the default
// where there is one, else a sample.
template <class Options>
std::string SampleToml(const SettingTable<Options>& table, const Setting<Options>& s) {
  const SettingValue d = table.Default(s);
  if (!std::holds_alternative<std::monostate>(d)) return FormatSettingValue(d);
  switch (s.info.kind) {
    case SettingKind::kReal: return "0.001";
    case SettingKind::kInteger: return "2";
    default: return "\"x\"";
  }
}

// Parses argv as the nsmodal command line; returns the parsed command line.
void Parse(cli::CommandLine& cl, std::vector<std::string> args) {
  args.insert(args.begin(), "nsmodal");
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  cl.app.parse(static_cast<int>(argv.size()), argv.data());
}

template <class Options>
void ExpectEverySceneKeyRead(const SettingTable<Options>& table, SettingPatch Scene::*section) {
  for (const Setting<Options>& s : table.settings()) {
    const std::string field = table.SceneField(s.info);
    if (field.empty()) continue;
    const std::string text =
        std::string(kSystem) + "[" + table.section() + "]\n" + s.info.scene_key + " = " + SampleToml(table, s) + "\n";
    const Scene scene = ParseScene(text);
    const SettingPatch& patch = scene.*section;
    ASSERT_EQ(patch.count(s.info.name), 1u) << field;
    const Configured<Options> c = table.Resolve({&patch});
    EXPECT_EQ(c.origin.at(s.info.name).source, SettingSource::kScene) << field;
    EXPECT_EQ(c.origin.at(s.info.name).field, field);
    EXPECT_EQ(c.names(s.info.name), field);
  }
}

TEST(Settings, TheSceneReadsEveryKeyOfBothTables) {
  ExpectEverySceneKeyRead(SimulateSettings(), &Scene::simulate);
  ExpectEverySceneKeyRead(ValidateSettings(), &Scene::validate);
}

TEST(Settings, ValidationTakesTheIntegratorTolerancesInItsOwnSceneTable) {
  // Declared once in simulate's table, lifted into validate's: [validate]
  // carries rtol (it could not before the tables), with validate's default.
  const Scene scene = ParseScene(std::string(kSystem) + "[validate]\nrtol = 1e-9\n");
  const Configured<ValidationRequest> c = ValidateSettings().Resolve({&scene.validate});
  EXPECT_EQ(c.options.options.simulate.rtol, 1e-9);
  EXPECT_EQ(c.origin.at("rtol").field, "validate.rtol");
  // The Moreau-Jean step: validation's default (1e-4) is not a simulation's (1e-3).
  EXPECT_EQ(RealOf(ValidateSettings().Default(*ValidateSettings().Find("step"))), 1e-4);
  EXPECT_EQ(RealOf(SimulateSettings().Default(*SimulateSettings().Find("step"))), 1e-3);
  // Threads are the machine's: no scene key.
  EXPECT_THROW(ParseScene(std::string(kSystem) + "[validate]\nthreads = 2\n"), InputError);
}

template <class Options>
void ExpectEveryFlag(const SettingTable<Options>& table, const std::string& command) {
  cli::CommandLine cl;
  CLI::App* app = cl.app.get_subcommand(command);
  std::set<std::string> declared;
  for (const Setting<Options>& s : table.settings()) {
    if (s.info.flag.empty() || !s.info.Takes(command)) continue;
    EXPECT_NO_THROW(app->get_option(s.info.flag)) << command << " lacks " << s.info.flag;
    declared.insert(s.info.flag);
  }
  // And no flag of the command is declared anywhere else: its scene and where
  // and how it writes (--out, --format) are the command's, not the run's
  // settings (no scene key, no Python keyword: Python returns arrays).
  for (const CLI::Option* o : app->get_options()) {
    const std::string name = o->get_name();
    if (name == "--help" || name == "--out" || name == "--format" || name == "scene") continue;
    EXPECT_EQ(declared.count(name), 1u) << command << "'s " << name << " is not made from the table";
  }
}

TEST(Settings, EveryCommandHasAFlagForEachOfItsSettingsAndNoOther) {
  ExpectEveryFlag(SimulateSettings(), "simulate");
  ExpectEveryFlag(ValidateSettings(), "validate");
}

TEST(Settings, EverySummaryWritesEverySettingAndItsSource) {
  const nlohmann::json sim = report::SimulationJson(SimulationSummary{}, SimulateSettings().Resolve({}));
  for (const auto& s : SimulateSettings().settings()) {
    EXPECT_TRUE(sim["settings"].contains(s.info.name)) << s.info.name;
    EXPECT_EQ(sim["settings_source"][s.info.name], "default") << s.info.name;
  }
  const nlohmann::json val = report::ValidationJson(ValidationReport{}, {}, ValidateSettings().Resolve({}));
  for (const auto& s : ValidateSettings().settings()) {
    EXPECT_TRUE(val["settings"].contains(s.info.name)) << s.info.name;
    EXPECT_EQ(val["settings_source"][s.info.name], "default") << s.info.name;
  }
}

TEST(Settings, TheReferenceListsEverySettingWithTheIssuesKeys) {
  const nlohmann::json ref = report::SettingsReferenceJson();
  ASSERT_EQ(ref.size(), SimulateSettings().settings().size() + ValidateSettings().settings().size());
  for (const nlohmann::json& s : ref) {
    for (const char* key : {"name", "scene_key", "flag", "python", "default", "unit", "doc", "commands"}) {
      EXPECT_TRUE(s.contains(key)) << s.dump() << " lacks " << key;
    }
  }
}

TEST(Settings, AValueFromTheSceneOverriddenByAFlagRemembersTheFlag) {
  const Scene scene = ParseScene(std::string(kSystem) + "[simulate]\nrtol = 1e-9\natol = 1e-13\n");
  cli::CommandLine cl;
  Parse(cl, {"simulate", "scene.toml", "--out", "out", "--rtol", "1e-8"});
  const Configured<SimulationRequest> c = SimulateSettings().Resolve({&scene.simulate, &cl.simulate.flags});
  EXPECT_EQ(c.options.options.rtol, 1e-8);
  EXPECT_EQ(c.origin.at("rtol").source, SettingSource::kFlag);
  EXPECT_EQ(c.origin.at("rtol").field, "--rtol");
  EXPECT_EQ(c.options.options.atol, 1e-13);
  EXPECT_EQ(c.origin.at("atol").source, SettingSource::kScene);
  EXPECT_EQ(c.origin.at("atol").field, "simulate.atol");
  EXPECT_EQ(c.origin.at("theta").source, SettingSource::kDefault);
  const nlohmann::json j = report::SimulationJson(SimulationSummary{}, c);
  EXPECT_EQ(j["settings_source"]["rtol"], "flag");
  EXPECT_EQ(j["settings_source"]["atol"], "scene");
  EXPECT_EQ(j["settings"]["rtol"], 1e-8);
}

// A refusal names what the user wrote: the flag when a flag gave the value,
// the scene key when the scene did.
TEST(Settings, ARefusalNamesTheFlagOrTheSceneKeyThatGaveTheValue) {
  const Scene scene = ParseScene(std::string(kSystem) + "[simulate]\nrtol = -1.0\n");
  auto field_of = [](const Configured<SimulationRequest>& c) {
    try {
      c.options.options.Validate(c.names);
    } catch (const InputError& e) {
      return e.field();
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(field_of(SimulateSettings().Resolve({&scene.simulate})), "simulate.rtol");
  cli::CommandLine cl;
  Parse(cl, {"simulate", "scene.toml", "--out", "out", "--rtol", "-2"});
  EXPECT_EQ(field_of(SimulateSettings().Resolve({&scene.simulate, &cl.simulate.flags})), "--rtol");
}

TEST(Settings, AnIntegerSettingRefusesAFractionNamingItsFlag) {
  cli::CommandLine cl;
  Parse(cl, {"validate", "scene.toml", "--out", "out", "--periods", "2.5"});
  try {
    ValidateSettings().Resolve({&cl.validate.flags});
    FAIL() << "--periods 2.5 was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--periods");
  }
}

}  // namespace
}  // namespace nsmodal
