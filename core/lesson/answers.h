#pragma once
// Answers files: what a student entered, for headless lessons and for
// rebuilding an attempt (lessons/README.md, "Answers files"). Either a chart
// (per tooth six depths and the bleeding sites) or a list of entries with their
// ticks (what an attempt stores), and the declared diagnosis; for inspection
// lessons the findings recorded on the odontogram and when it was submitted.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/lesson/lesson.h"

namespace sulcus {

struct Answers {
  std::vector<ChartEntry> entries;
  std::optional<DeclaredDiagnosis> diagnosis;
  // Inspection lessons: the odontogram's findings and when it was submitted
  // (kAfterReading: at the end).
  std::vector<Finding> findings;
  std::optional<std::uint64_t> submitted;
  std::vector<ViewSample> views;  // the window's camera as it moved
};

/// Throws LoadError with every error as `file:line:column: message`.
Answers LoadAnswers(const std::filesystem::path& file);

/// Writes the entries form (every entry with its tick); LoadAnswers reads it back.
void SaveAnswers(const Answers& answers, const std::filesystem::path& file);

}  // namespace sulcus
