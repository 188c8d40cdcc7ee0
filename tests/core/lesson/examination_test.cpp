// The full periodontal examination (lessons/periodontal_examination.yaml) taken
// by the careful scripted student on the whole mouth: every tooth present read
// and charted, the missing teeth charted as missing, and the stage, extent and
// grade of the truth declared. Minutes (the scene's 26 gingiva shares are built
// once into the test's cache), so the slow tier.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include "core/lesson/attempt.h"
#include "core/lesson/scripted_student.h"
#include "tests/common/output.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

TEST(Examination, TheCarefulStudentExaminesTheWholeMouth) {
  AttemptOptions o;
  o.student = "careful";
  o.device = "student:careful";
  o.cache_dir = fs::path(SULCUS_TEST_OUTPUT) / "examination-cache";
  const auto t0 = std::chrono::steady_clock::now();
  const AttemptOutcome out = RunAttempt(
      fs::path(SULCUS_SOURCE_DIR) / "lessons" / "periodontal_examination.yaml", o);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const LessonResult& r = out.result;
  std::printf(
      "full examination: %d sites read, %d charted, score %.1f, %.1f s of "
      "lesson in %.1f s (scene build included)\n",
      r.sites_read, r.sites_charted, r.total, r.duration_s, wall);

  // 28 teeth less 36 and 25: 26 teeth, 156 sites, every one read and charted
  // within a millimetre of its truth.
  EXPECT_EQ(r.sites.size(), 156u);
  EXPECT_EQ(r.sites_read, 156);
  EXPECT_EQ(r.sites_charted, 156);
  std::set<int> teeth;
  for (const SiteResult& s : r.sites) {
    teeth.insert(s.site.fdi);
    ASSERT_TRUE(s.reached_mm) << s.site.ToString();
    EXPECT_LE(std::abs(*s.reached_mm - s.truth_mm), 1.0) << s.site.ToString();
    ASSERT_TRUE(s.entry && s.entry->pd_mm) << s.site.ToString();
    EXPECT_LE(std::abs(*s.entry->pd_mm - s.truth_mm), 1) << s.site.ToString();
  }
  EXPECT_EQ(teeth.size(), 26u);
  EXPECT_EQ(teeth.count(36), 0u);
  EXPECT_EQ(teeth.count(25), 0u);
  // The chart records the missing teeth as missing, and the lost one counts.
  ASSERT_NE(r.true_chart.Find(36), nullptr);
  EXPECT_FALSE(r.true_chart.Find(36)->present);
  ASSERT_NE(r.true_chart.Find(25), nullptr);
  EXPECT_FALSE(r.true_chart.Find(25)->present);
  EXPECT_EQ(r.true_chart.patient.teeth_lost_to_periodontitis, 1);

  EXPECT_GE(r.total, 95.0);
  EXPECT_EQ(r.true_dx.Summary(), "periodontitis stage III, generalized, grade B");
  ASSERT_TRUE(r.declared);
  EXPECT_EQ(r.declared->Summary(), r.true_dx.Summary());
  for (const StepResult& s : r.steps) EXPECT_TRUE(s.completed) << s.id;
}

// The whole examination by keys: the "keys" student (N, R, the walking keys
// and T on the window's own key device) reads and charts every site of the
// whole mouth. Prints the lesson's time (a person at the keys takes longer:
// the student presses a key every 0.05 to 0.6 s) and every site read more
// than a millimetre off its truth, with why.
TEST(Examination, TheKeysStudentExaminesTheWholeMouthByKeys) {
  AttemptOptions o;
  o.student = "keys";
  o.device = "student:keys";
  o.cache_dir = fs::path(SULCUS_TEST_OUTPUT) / "examination-cache";
  const AttemptOutcome out = RunAttempt(
      fs::path(SULCUS_SOURCE_DIR) / "lessons" / "periodontal_examination.yaml", o);
  const LessonResult& r = out.result;
  int within = 0;
  for (const SiteResult& s : r.sites) {
    if (s.reached_mm && std::abs(*s.reached_mm - s.truth_mm) <= 1.0) {
      ++within;
      continue;
    }
    std::printf("figure: by keys, %s read %s (true %d mm)\n", s.site.ToString().c_str(),
                s.reached_mm
                    ? (std::to_string(*s.reached_mm).substr(0, 4) + " mm").c_str()
                    : "nothing",
                s.truth_mm);
  }
  std::printf(
      "figure: the whole examination by keys: %d of %zu sites read within 1 mm, %d "
      "charted, score %.1f, %.1f min of lesson\n",
      within, r.sites.size(), r.sites_charted, r.total, r.duration_s / 60);
  EXPECT_EQ(r.sites_charted, 156);
  EXPECT_EQ(within, 156) << "every site within 1 mm (moved lines included)";
  EXPECT_GE(r.total, 98.0);
  EXPECT_LE(r.duration_s, 30 * 60.0);
  ASSERT_TRUE(r.declared);
  EXPECT_EQ(r.declared->Summary(), r.true_dx.Summary());
}

}  // namespace
}  // namespace sulcus
