#include "core/base/load_error.h"

namespace sulcus {

std::string ErrorAt::ToString() const {
  return file + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " +
         message;
}

LoadError::LoadError(std::string kind, std::vector<ErrorAt> errors)
    : std::runtime_error([&] {
        std::string s;
        for (const ErrorAt& e : errors) s += (s.empty() ? "" : "\n") + e.ToString();
        return s;
      }()),
      kind_(std::move(kind)),
      errors_(std::move(errors)) {}

std::string LoadError::Summary() const {
  std::string s = kind_;
  if (!errors_.empty()) s += " " + errors_.front().file;
  s += ": " + std::to_string(errors_.size()) +
       (errors_.size() == 1 ? " error" : " errors");
  return s;
}

}  // namespace sulcus
