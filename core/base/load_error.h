#pragma once
// What reading a file found wrong, with where: every YAML file Sulcus reads
// (scenes, lessons, answers, attempt markers) reports all its errors at once,
// each as `file:line:column: message`.

#include <stdexcept>
#include <string>
#include <vector>

namespace sulcus {

/// One error and where it is.
struct ErrorAt {
  std::string file;
  int line = 0;    // 1-based; 0 when it is the whole file
  int column = 0;  // 1-based
  std::string message;
  std::string ToString() const;  // "file:line:column: message"
};

/// Thrown by a reader with every error found; what() lists them one a line.
/// `kind` names what the file was read as ("scene file", "lesson file",
/// "answers file", "attempt marker"): a lesson's errors may include its scene's.
class LoadError : public std::runtime_error {
 public:
  LoadError(std::string kind, std::vector<ErrorAt> errors);
  const std::string& kind() const { return kind_; }
  const std::vector<ErrorAt>& errors() const { return errors_; }
  /// One line for a heading: "lesson file lessons/x.yaml: 2 errors" (the file
  /// of the first error).
  std::string Summary() const;

 private:
  std::string kind_;
  std::vector<ErrorAt> errors_;
};

}  // namespace sulcus
