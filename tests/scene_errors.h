#pragma once
// A scene that must be refused: the error names the field, and the offending
// value where there is one.
#include <gtest/gtest.h>

#include <string>

#include "nsmodal/error.h"
#include "nsmodal/scene.h"

namespace nsmodal::testing {

inline void ExpectSceneError(const std::string& toml, const std::string& field, const std::string& value = "") {
  try {
    ParseScene(toml);
    FAIL() << "no error for:\n" << toml;
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(std::string(e.what()).find(value), std::string::npos) << e.what();
  }
}

}  // namespace nsmodal::testing
