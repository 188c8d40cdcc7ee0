#pragma once
// A stored attempt's worth of result for the results store's tests: 24 sites
// (46 DB charted 5 mm), 120 rubric lines with commas and quotes, two categories.

#include <string>

#include "core/lesson/lesson.h"

namespace sulcus::test {

inline LessonResult Sample(const std::string& student, double total) {
  LessonResult r;
  r.lesson_name = "Periodontal probing";
  r.lesson_file = "/lessons/periodontal_probing.yaml";
  r.scene_file = "/scenes/periodontal_probing.yaml";
  r.mode = "practice";
  r.student = student;
  r.total = total;
  r.sites_total = 24;
  for (int t : {47, 46, 45, 44})
    for (int s = 0; s < 6; ++s) {
      SiteResult x;
      x.site = {t, s};
      x.truth_mm = 3;
      x.reached_mm = 3.1;
      ChartEntry e;
      e.site = x.site;
      e.pd_mm = (t == 46 && s == 2) ? 5 : 3;
      e.tick = 100;
      x.entry = e;
      x.peak_force_n = 0.22;
      r.sites.push_back(x);
    }
  for (int i = 0; i < 120; ++i) {
    RubricLine l;
    l.category = i % 2 ? "technique" : "force";
    l.status = RubricLine::Status::kPass;
    l.credit = 1;
    l.message = "line " + std::to_string(i) + ", with a comma and \"quotes\"";
    l.tick = static_cast<std::uint64_t>(i);
    r.lines.push_back(l);
  }
  r.category_credit = {{"technique", 1.0}, {"force", 0.5}};
  r.category_weight = {{"technique", 20}, {"force", 15}};
  return r;
}

}  // namespace sulcus::test
