// The scalar parameters of a model (parameter.h, issue 26): named by their
// scene keys, read, changed and checked as a scene is.
#include <gtest/gtest.h>

#include <string>

#include "nsmodal/error.h"
#include "nsmodal/parameter.h"
#include "nsmodal/scene.h"

namespace nsmodal {
namespace {

const char* kForced = R"(
[system]
masses = [1.0, 1.0]
springs = [0.85, 2.0]
gap = 1.0
restitution = 0.8
damping_ratios = [0.02, 0.02]
[forcing]
amplitude = [0.0, 0.1]
frequency = 0.6
)";

const char* kTwoContacts = R"(
[system]
masses = [1.0, 1.0]
springs = [0.85, 2.0]
rayleigh_damping = [0.01, 0.0]
[[contact]]
dof = 2
gap = 1.0
restitution = 0.9
[[contact]]
dof = 2
side = "lower"
gap = 1.2
restitution = 0.7
)";

// The message of the InputError `f` throws ("" if none).
template <class F>
std::string Refusal(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Parameter, ReadsEachKeyAsTheSceneGivesIt) {
  const Model forced = ParseScene(kForced).model;
  EXPECT_EQ(ParameterValue(forced, ParseModelParameter(forced, "frequency")), 0.6);
  EXPECT_EQ(ParameterValue(forced, ParseModelParameter(forced, "amplitude")), 0.1);
  EXPECT_EQ(ParameterValue(forced, ParseModelParameter(forced, "gap")), 1.0);
  EXPECT_EQ(ParameterValue(forced, ParseModelParameter(forced, "restitution")), 0.8);
  EXPECT_EQ(ParameterValue(forced, ParseModelParameter(forced, "masses[2]")), 1.0);
  EXPECT_EQ(ParameterValue(forced, ParseModelParameter(forced, "springs[1]")), 0.85);
  EXPECT_EQ(ParameterValue(forced, ParseModelParameter(forced, "damping_ratios[1]")), 0.02);
  const Model two = ParseScene(kTwoContacts).model;
  EXPECT_EQ(ParameterValue(two, ParseModelParameter(two, "contact[2].gap")), 1.2);
  EXPECT_EQ(ParameterValue(two, ParseModelParameter(two, "contact[1].restitution")), 0.9);
  EXPECT_EQ(ParameterValue(two, ParseModelParameter(two, "rayleigh_damping[1]")), 0.01);
}

TEST(Parameter, ChangesTheModelAsTheSceneWithThatValueWould) {
  // springs[2] = 3: the scene with springs = [0.85, 3.0], bit for bit, its
  // modal damping rebuilt on the new modes.
  const Model forced = ParseScene(kForced).model;
  const Model changed = WithParameter(forced, ParseModelParameter(forced, "springs[2]"), 3.0);
  std::string text = kForced;
  text.replace(text.find("springs = [0.85, 2.0]"), 21, "springs = [0.85, 3.0]");
  const Model expected = ParseScene(text).model;
  EXPECT_EQ(changed.stiffness, expected.stiffness);
  EXPECT_EQ(changed.damping, expected.damping);
  EXPECT_NE(changed.damping, forced.damping);
  // The amplitude scales the force vector: its shape is kept.
  const Model louder = WithParameter(forced, ParseModelParameter(forced, "amplitude"), 0.3);
  EXPECT_EQ(louder.forcing.amplitude[0], 0.0);
  // (Scaled by 0.3 / 0.1: one rounding of the product, 3e-17 at 0.3.)
  EXPECT_NEAR(louder.forcing.amplitude[1], 0.3, 1e-16);
  // One parameter after another: the first one's value is kept.
  const Model both = WithParameter(changed, ParseModelParameter(changed, "gap"), 0.5);
  EXPECT_EQ(both.FirstContact().gap, 0.5);
  EXPECT_EQ(both.stiffness, expected.stiffness);
  // A model built in code (no keys) changes in place where it can.
  const Model paper = PaperModel();
  EXPECT_EQ(WithParameter(paper, ParseModelParameter(paper, "restitution"), 0.5).FirstContact().restitution, 0.5);
}

TEST(Parameter, RefusesNamesThatAreNotParametersOfThisModel) {
  const Model forced = ParseScene(kForced).model;
  const Model two = ParseScene(kTwoContacts).model;
  auto refusal = [](const Model& m, const std::string& name) {
    return Refusal([&] { ParseModelParameter(m, name, "--parameter"); });
  };
  EXPECT_NE(refusal(forced, "stiffness").find("--parameter: 'stiffness' is not a parameter"), std::string::npos);
  EXPECT_NE(refusal(forced, "masses[3]").find("the model has 2 masses"), std::string::npos);
  EXPECT_NE(refusal(forced, "masses[0]").find("takes an index from 1"), std::string::npos);
  EXPECT_NE(refusal(forced, "masses").find("takes an index from 1"), std::string::npos);
  EXPECT_NE(refusal(two, "gap").find("the model has 2 contacts: name one, contact[j].gap"), std::string::npos);
  EXPECT_NE(refusal(two, "contact[3].gap").find("the model has 2 contacts"), std::string::npos);
  EXPECT_NE(refusal(two, "frequency").find("no harmonic force"), std::string::npos);
  EXPECT_NE(refusal(two, "damping_ratios[1]").find("carries no damping_ratios key"), std::string::npos);
  EXPECT_NE(refusal(PaperModel(), "masses[1]").find("not a chain"), std::string::npos);
}

TEST(Parameter, AValueOutsideTheValidModelNamesTheSceneField) {
  const Model forced = ParseScene(kForced).model;
  auto refusal = [&](const std::string& name, double value) {
    return Refusal([&] { WithParameter(forced, ParseModelParameter(forced, name), value); });
  };
  EXPECT_NE(refusal("masses[1]", -1.0).find("system.masses"), std::string::npos);
  EXPECT_NE(refusal("restitution", 1.5).find("system.restitution"), std::string::npos);
  EXPECT_NE(refusal("gap", 0.0).find("system.gap"), std::string::npos);
  EXPECT_NE(refusal("frequency", -0.2).find("forcing.frequency"), std::string::npos);
  EXPECT_NE(refusal("damping_ratios[2]", -0.1).find("system.damping_ratios"), std::string::npos);
  const Model paper = PaperModel();
  EXPECT_NE(Refusal([&] { WithParameter(paper, ParseModelParameter(paper, "restitution"), 1.5); })
                .find("system.restitution"),
            std::string::npos);
}

}  // namespace
}  // namespace nsmodal
