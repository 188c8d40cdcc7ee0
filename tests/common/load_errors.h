#pragma once
// A reader's errors as the lines a user reads ("file:line:column: message"),
// for tests that compare them: empty when the file was accepted.

#include <string>
#include <vector>

#include "core/base/load_error.h"

namespace sulcus::test {

template <typename Load>
std::vector<std::string> ErrorLines(Load&& load) {
  try {
    load();
  } catch (const LoadError& e) {
    std::vector<std::string> lines;
    for (const ErrorAt& x : e.errors()) lines.push_back(x.ToString());
    return lines;
  }
  return {};
}

}  // namespace sulcus::test
