#pragma once
// Each group of subcommands registers itself on the CLI11 app.

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdlib>
#include <string>

#include "core/lesson/results.h"

namespace sulcus::cli {

/// `mesh info`, `mesh convert`, `mesh make`.
void AddMeshCommands(CLI::App& app);

/// `spheretree build`, `spheretree eval`.
void AddSphereTreeCommands(CLI::App& app);

/// `qp-bench`, `qp-gen`.
void AddQpCommands(CLI::App& app);

/// `accuracy-cost`.
void AddAccuracyCommands(CLI::App& app);

/// `anatomy tooth`.
void AddAnatomyCommands(CLI::App& app);

/// `scene validate`, `scene export`.
void AddSceneCommands(CLI::App& app);

/// `run`, `devices`, `recording export|info`.
void AddRunCommands(CLI::App& app);

/// `lesson validate|run|report|recover|case`, `results list|show|export|sync`.
void AddLessonCommands(CLI::App& app);

/// `results roster list|add|reset|sign-in` on the `results` command.
void AddRosterCommands(CLI::App* results);

/// The results place of a --results option (a folder or a PostgreSQL URL
/// without its password; default: $SULCUS_RESULTS_URL, else the default
/// folder's results.db).
ResultsPlace ResultsOf(const std::string& option);
/// Asks for the instructor's passphrase ($SULCUS_INSTRUCTOR_PASSPHRASE, or
/// typed) and checks it for the store of `option`; throws
/// std::invalid_argument saying what is wrong.
void RequireInstructor(const std::string& results_option);

/// The student's sign-in for `lesson run`: the passphrase from
/// $SULCUS_STUDENT_PASSPHRASE or the first line of `passphrase_file`; "" when
/// neither is given. Throws std::invalid_argument for a file that cannot be read.
std::string StudentPassphrase(const std::string& passphrase_file);

/// How a command that has printed all it has to say ends with a failing exit
/// status (a mesh that is not a solid, a scene with errors, a lesson not
/// passed): `Finish(status)` returns for 0 and throws CommandStatus otherwise,
/// which main() returns, with no further message.
struct CommandStatus {
  int code;
};
inline void Finish(int status) {
  if (status != 0) throw CommandStatus{status};
}

/// A number option's value must be finite (CLI::Range lets NaN through: every
/// comparison with it is false): "nan", "inf" and 1e999 are refused.
inline const CLI::Validator& Finite() {
  static const CLI::Validator v(
      [](std::string& s) -> std::string {
        char* end = nullptr;
        const double x = std::strtod(s.c_str(), &end);
        if (end == s.c_str() || *end != '\0')
          return "'" + s.substr(0, 80) + "' is not a number";
        if (!std::isfinite(x)) return "'" + s.substr(0, 80) + "' is not a finite number";
        return {};
      },
      "FINITE");
  return v;
}

/// A whole number from 0 up (a count, an index, a seed): "-5" is refused
/// rather than read as something else.
inline const CLI::Validator& WholeNumber() {
  static const CLI::Validator v(
      [](std::string& s) -> std::string {
        if (s.empty() || s.size() > 19 ||
            s.find_first_not_of("0123456789") != std::string::npos)
          return "'" + s.substr(0, 80) +
                 "' is not a whole number from 0 to 9223372036854775807";
        return {};
      },
      "WHOLE");
  return v;
}

}  // namespace sulcus::cli
