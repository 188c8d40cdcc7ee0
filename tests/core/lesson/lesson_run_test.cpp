// The lesson's run tick by tick, without a scripted student: what "Next"
// points at, practice against assessment, a reading completed by charting,
// and a device lost mid-attempt.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "core/haptics/tip_locator.h"
#include "core/lesson/lesson.h"
#include "core/lesson/report.h"
#include "core/scene/scene.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

fs::path Lesson() {
  return fs::path(SULCUS_SOURCE_DIR) / "lessons" / "periodontal_probing.yaml";
}
fs::path Cache() { return fs::path(SULCUS_TEST_OUTPUT) / "probing-cache"; }

// The tip held 6.8 mm down 46 DB's line for `dwell` ticks from tick 1, then
// lifted far away for `away` ticks.
std::vector<TickRecord> DwellAt46DB(const CompiledScene& scene, int dwell, int away) {
  const auto& sites = scene.effects.sites;
  const auto it = std::find_if(sites.begin(), sites.end(), [](const ProbingSite& p) {
    return p.fdi == 46 && p.site == 2;
  });
  EXPECT_NE(it, sites.end());
  const Vector3 down = (it->floor_W - it->margin_W).normalized();
  std::vector<TickRecord> out;
  for (int i = 0; i < dwell + away; ++i) {
    TickRecord r;
    r.tick = static_cast<std::uint64_t>(i + 1);
    const Vector3 p = i < dwell ? Vector3(it->margin_W + 6.8 * down)
                                : Vector3(it->margin_W - 30.0 * down);
    r.X_WG = RigidTransform(Quaternion::FromTwoVectors(Vector3::UnitZ(), -down), p);
    r.force_W = -0.22 * down;  // the floor pushing back up the probe
    out.push_back(r);
  }
  return out;
}

TEST(LessonRun, PracticeShowsTheTruthAssessmentDoesNot) {
  LessonSpec spec = LoadLessonSpec(Lesson());
  const auto scene = CompileScene(LoadSceneSpec(spec.scene), Cache());
  for (const auto mode : {LessonSpec::Mode::kPractice, LessonSpec::Mode::kAssessment}) {
    spec.mode = mode;
    LessonRun lesson(spec, *scene, "x");
    const auto ticks = DwellAt46DB(*scene, 300, 200);
    for (int i = 0; i < 300; ++i) lesson.OnTick(ticks[static_cast<std::size_t>(i)]);
    ASSERT_TRUE(lesson.tip_site());
    EXPECT_EQ(lesson.tip_site()->ToString(), "46 DB") << "the panel's site";
    EXPECT_TRUE(lesson.feedback().empty()) << "the visit has not ended";
    for (int i = 300; i < 500; ++i) lesson.OnTick(ticks[static_cast<std::size_t>(i)]);
    EXPECT_FALSE(lesson.tip_site());
    ASSERT_EQ(lesson.feedback().size(), 1u);
    const bool truth_shown =
        lesson.feedback()[0].find("true depth is 7 mm") != std::string::npos;
    EXPECT_EQ(truth_shown, mode == LessonSpec::Mode::kPractice) << lesson.feedback()[0];
    ASSERT_TRUE(lesson.next_site());
    EXPECT_EQ(lesson.next_site()->ToString(), "46 B")
        << "on along the path from the site the student read (47's come round)";
  }
}

TEST(LessonRun, ChartingASiteWithTheTipInItCompletesItsReading) {
  const LessonSpec spec = LoadLessonSpec(Lesson());
  const auto scene = CompileScene(LoadSceneSpec(spec.scene), Cache());
  const auto ticks = DwellAt46DB(*scene, 400, 0);
  LessonRun live(spec, *scene, "x");
  for (int i = 0; i < 200; ++i) live.OnTick(ticks[static_cast<std::size_t>(i)]);
  ChartEntry e;
  e.site = {46, 2};
  e.pd_mm = 7;
  e.tick = live.last_tick() + 1;  // as the window stamps it
  live.Enter(e);
  for (int i = 200; i < 400; ++i) live.OnTick(ticks[static_cast<std::size_t>(i)]);
  const LessonResult a = live.Finish();
  const SiteResult* s = nullptr;
  for (const SiteResult& x : a.sites)
    if (x.site == SiteRef{46, 2}) s = &x;
  ASSERT_NE(s, nullptr);
  ASSERT_TRUE(s->reached_mm) << "read while the tip rests at the floor";
  EXPECT_NEAR(*s->reached_mm, 6.8, 1e-9);
  EXPECT_EQ(s->insertions, 1) << "one dwell, one reading";
  EXPECT_EQ(s->reading_tick, 1u);
  EXPECT_NEAR(s->held_force_n, 0.22, 0.01) << "the force held (low-passed, median)";
  // The same entry replayed from the answers file at its tick: the same report.
  LessonRun replay(spec, *scene, "x");
  replay.Schedule(e);
  for (const TickRecord& r : ticks) replay.OnTick(r);
  replay.OnEnd();
  EXPECT_EQ(ReportJson(replay.Finish(), {}), ReportJson(a, {}));
  // Every site without a reading says why.
  for (const SiteResult& x : a.sites) {
    if (x.reached_mm) continue;
    EXPECT_FALSE(x.no_reading.empty()) << x.site.ToString();
  }
}

TEST(LessonRun, ALostDeviceIsNamedWithItsMomentsAndTheAttemptIsIncomplete) {
  const LessonSpec spec = LoadLessonSpec(Lesson());
  const auto scene = CompileScene(LoadSceneSpec(spec.scene), Cache());
  LessonRun lesson(spec, *scene, "x");
  TickRecord r;
  for (std::uint64_t t = 1; t <= 3000; ++t) {
    r.tick = t;
    r.num_events = 0;
    if (t == 1000 || t == 2600)
      r.events[r.num_events++] = HapticEvent::Of(EventKind::kDeviceLost);
    if (t == 1500) r.events[r.num_events++] = HapticEvent::Of(EventKind::kDeviceBack);
    lesson.OnTick(r);
    EXPECT_EQ(lesson.device_lost(), (t >= 1000 && t < 1500) || t >= 2600) << t;
  }
  lesson.SetEnding(
      "the device stopped answering and the lesson was finished before the last step");
  const LessonResult res = lesson.Finish();
  EXPECT_FALSE(res.complete);
  EXPECT_EQ(
      res.ended,
      "the device stopped answering and the lesson was finished before the last step");
  ASSERT_EQ(res.interruptions.size(), 2u);
  EXPECT_EQ(res.interruptions[0].lost_tick, 1000u);
  EXPECT_EQ(res.interruptions[0].back_tick, 1500u);
  EXPECT_EQ(res.interruptions[1].back_tick, 0u);
  std::vector<std::string> said;
  for (const RubricLine& l : res.lines)
    if (l.category == "time") said.push_back(l.message);
  EXPECT_NE(std::find(said.begin(), said.end(),
                      "the device stopped answering at 1.0 s and was back 0.5 s later"),
            said.end());
  EXPECT_NE(std::find(said.begin(), said.end(),
                      "the device stopped answering at 2.6 s and did not come back"),
            said.end());
  EXPECT_NE(std::find(said.begin(), said.end(), "incomplete: " + res.ended), said.end());
  const std::string json = ReportJson(res, {});
  EXPECT_NE(json.find("\"complete\": false"), std::string::npos);
  EXPECT_NE(json.find("{\"lost_tick\": 1000, \"back_tick\": 1500}"), std::string::npos);
  EXPECT_NE(ReportHtml(res, {}).find("Incomplete attempt"), std::string::npos);
}

}  // namespace
}  // namespace sulcus
