#pragma once
// The report of an attempt, for machines (JSON) and for people (one
// self-contained HTML page: the periodontal chart with truth, entry and reached
// depth per site, the per-site signed error map, the force trace of every site
// against the band, the walking-stroke coverage, the diagnosis of the true
// chart, of the student's chart and the declared one with the 2017 decision
// path, and every rubric line with its moment). Pictures are inline SVG, so
// the page opens anywhere without Sulcus.

#include <filesystem>
#include <string>

#include "core/lesson/answers.h"
#include "core/lesson/lesson.h"

namespace sulcus {

struct ReportInfo {
  std::string recording;        // the attempt's recording (for replay), may be empty
  std::string started;          // when the attempt started, ISO 8601
  std::int64_t attempt_id = 0;  // in the results database, 0 when not stored
};

std::string ReportJson(const LessonResult& r, const ReportInfo& info);
std::string ReportHtml(const LessonResult& r, const ReportInfo& info);

/// Writes report.json and report.html into `dir` (created), each through a
/// temporary file and a rename, so a report is whole or absent.
void WriteReport(const LessonResult& r, const ReportInfo& info,
                 const std::filesystem::path& dir);

}  // namespace sulcus
