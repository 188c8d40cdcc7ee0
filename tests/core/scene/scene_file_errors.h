#pragma once
// Scene files written for a test and the errors LoadSceneSpec gives for them,
// shared by the scene file's test files.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "core/scene/scene.h"
#include "tests/common/output.h"

namespace sulcus::test {

inline std::filesystem::path Dir() { return test::OutputPath("scenes"); }

inline std::filesystem::path Write(const std::string& name, const std::string& yaml) {
  return test::WriteText(Dir() / name, yaml);
}

// Loads `yaml` and returns every error as "line:column: message" (file stripped).
// Each call writes its own file: ctest runs these tests in parallel.
inline std::vector<std::string> Errors(const std::string& yaml) {
  static int calls = 0;
  const std::filesystem::path p =
      Write(std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
                "_" + std::to_string(++calls) + ".yaml",
            yaml);
  try {
    LoadSceneSpec(p);
  } catch (const LoadError& e) {
    std::vector<std::string> out;
    for (const ErrorAt& err : e.errors()) {
      EXPECT_EQ(err.file, p.string());
      EXPECT_EQ(err.ToString().rfind(p.string() + ":", 0), 0u);
      out.push_back(std::to_string(err.line) + ":" + std::to_string(err.column) + ": " +
                    err.message);
    }
    return out;
  }
  return {"accepted"};
}

using Lines = std::vector<std::string>;

}  // namespace sulcus::test
