#include "core/base/load_error.h"

namespace sulcus {

std::string ErrorAt::ToString() const {
  return file + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " +
         message;
}

LoadError::LoadError(std::vector<ErrorAt> errors)
    : std::runtime_error([&] {
        std::string s;
        for (const ErrorAt& e : errors) s += (s.empty() ? "" : "\n") + e.ToString();
        return s;
      }()),
      errors_(std::move(errors)) {}

}  // namespace sulcus
