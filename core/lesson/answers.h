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
  // Where each entry was written (line, column; 1-based), parallel to `entries`:
  // for errors found when the answers meet their lesson.
  std::vector<std::pair<int, int>> entry_at;
  std::filesystem::path file;
};

/// Throws LoadError with every error as `file:line:column: message`: among
/// them a depth of 0 (a depth is 1 to 15 mm), a tooth that is not an FDI
/// number, a site given twice where either has no tick (with a tick, a later
/// entry is a correction; the last wins), a tooth twice in the chart.
Answers LoadAnswers(const std::filesystem::path& file);

/// Checks the answers against the lesson they are for: every entry's tooth is
/// one of the lesson's teeth. Throws LoadError naming each entry that is not.
void CheckAnswersFor(const Answers& answers, const std::vector<int>& lesson_teeth);

/// Writes the entries form (every entry with its tick); LoadAnswers reads it back.
void SaveAnswers(const Answers& answers, const std::filesystem::path& file);

}  // namespace sulcus
