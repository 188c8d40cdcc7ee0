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

}  // namespace
}  // namespace sulcus
