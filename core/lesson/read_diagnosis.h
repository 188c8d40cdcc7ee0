#pragma once
// The stage and the grade as lesson and answers files give them (private to
// core/lesson): each read or refused with its place and what is expected.

#include <optional>
#include <string>

#include "core/base/yaml_reader.h"
#include "core/lesson/chart.h"

namespace sulcus {

/// `stage: I` to `IV`; empty (and an error) otherwise.
inline std::optional<Stage> ReadStage(YamlReader& r, const YAML::Node& n) {
  const std::string st = r.Text(n, "stage");
  const auto stage = StageFromString(st);
  if (stage && *stage != Stage::kNone) return stage;
  r.Error(n, "'stage' must be I, II, III or IV, not '" + st + "'");
  return std::nullopt;
}

/// `grade: A`, `B` or `C`; empty (and an error) otherwise.
inline std::optional<Grade> ReadGrade(YamlReader& r, const YAML::Node& n) {
  const std::string g = r.Text(n, "grade");
  const auto grade = GradeFromString(g);
  if (grade && *grade != Grade::kNone) return grade;
  r.Error(n, "'grade' must be A, B or C, not '" + g + "'");
  return std::nullopt;
}

}  // namespace sulcus
