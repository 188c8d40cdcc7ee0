// Lessons end to end on the shipped probing lesson: scripted students with
// known behaviour get exactly the rubric lines they earn; a replayed attempt
// gives the same report; an attempt cut short is rebuilt. (Lesson and answers
// files have their own tests: lesson_file_test.cpp, answers_test.cpp.)
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>
#include <set>

#include "core/base/text.h"
#include "core/haptics/recording.h"
#include "core/haptics/scripted_device.h"
#include "core/haptics/tip_locator.h"
#include "core/lesson/attempt.h"
#include "core/lesson/report.h"
#include "core/lesson/results.h"
#include "core/lesson/scripted_student.h"
#include "tests/common/kill_sweep.h"
#include "tests/common/output.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

fs::path Lesson() {
  return fs::path(SULCUS_SOURCE_DIR) / "lessons" / "periodontal_probing.yaml";
}
fs::path Out(const std::string& name) { return test::OutputPath("lesson", name); }
fs::path Cache() { return fs::path(SULCUS_TEST_OUTPUT) / "probing-cache"; }

AttemptOutcome Take(const std::string& student, const fs::path& record = {}) {
  AttemptOptions o;
  o.student = student;
  o.device = "student:" + student;
  o.cache_dir = Cache();
  o.record = record;
  return RunAttempt(Lesson(), o);
}

std::vector<const RubricLine*> Lines(const LessonResult& r, const std::string& category,
                                     RubricLine::Status status) {
  std::vector<const RubricLine*> v;
  for (const RubricLine& l : r.lines)
    if (l.category == category && l.status == status) v.push_back(&l);
  return v;
}

std::set<std::string> Sites(const std::vector<const RubricLine*>& lines) {
  std::set<std::string> s;
  for (const RubricLine* l : lines)
    if (l->site) s.insert(l->site->ToString());
  return s;
}

TEST(GeneratedCase, DrawsAChartWithTheAskedDiagnosisAndTheSeedRebuildsIt) {
  const LessonSpec spec = LoadLessonSpec(Lesson());
  const SceneSpec scene = LoadSceneSpec(spec.scene);
  for (const auto& [stage, extent] : {std::pair{Stage::kIII, Extent::kLocalized},
                                      std::pair{Stage::kII, Extent::kGeneralized},
                                      std::pair{Stage::kI, Extent::kGeneralized}}) {
    CaseSpec c;
    c.generated = true;
    c.stage = stage;
    c.extent = extent;
    std::set<std::string> distinct;
    for (std::uint64_t seed = 1; seed <= 10; ++seed) {
      const SceneSpec s = ApplyCase(scene, spec.teeth, c, seed);
      const Diagnosis d = Classify2017(TrueChart(s, spec.teeth));
      EXPECT_EQ(d.stage, stage) << "seed " << seed;
      EXPECT_EQ(d.extent, extent) << "seed " << seed;
      std::string key;
      for (const ObjectSpec& o : s.objects)
        for (double p : o.pocket_mm) key += std::to_string(static_cast<int>(p));
      distinct.insert(key);
      // The same seed, the same case.
      const SceneSpec again = ApplyCase(scene, spec.teeth, c, seed);
      for (std::size_t i = 0; i < s.objects.size(); ++i)
        EXPECT_EQ(s.objects[i].pocket_mm, again.objects[i].pocket_mm);
    }
    EXPECT_GE(distinct.size(), 5u) << "cases cannot be learnt by heart";
  }
}

TEST(Students, TheCarefulOneScoresNearlyFull) {
  const AttemptOutcome out = Take("careful");
  const LessonResult& r = out.result;
  EXPECT_EQ(r.sites_read, 24);
  EXPECT_EQ(r.sites_charted, 24);
  for (const SiteResult& s : r.sites) {
    ASSERT_TRUE(s.reached_mm) << s.site.ToString();
    EXPECT_LE(std::abs(*s.reached_mm - s.truth_mm), 0.5) << s.site.ToString();
    EXPECT_GE(s.peak_force_n, 0.15) << s.site.ToString();
    EXPECT_LE(s.peak_force_n, 0.30) << s.site.ToString();
    if (!IsInterdental(s.site.site)) {
      EXPECT_LE(s.angle_deg, 5.0) << s.site.ToString();
    }
  }
  for (const RubricLine& l : r.lines)
    EXPECT_NE(l.status, RubricLine::Status::kFail) << l.message;
  EXPECT_GE(r.total, 95.0);
  ASSERT_TRUE(r.declared);
  EXPECT_EQ(r.declared->Summary(), r.true_dx.Summary());
  EXPECT_EQ(r.true_dx.Summary(), "periodontitis stage III, localized");
  for (const StepResult& s : r.steps) EXPECT_TRUE(s.completed) << s.id;
  // Every line names a moment inside the attempt.
  for (const RubricLine& l : r.lines) {
    EXPECT_GE(l.tick, r.first_tick) << l.message;
    EXPECT_LE(l.tick, r.last_tick + 1) << l.message;
  }
}

// Examiner calibration against a reference examiner (the instructor's chart,
// lessons/calibration/): the examiner read 46 DB and 47 MB 1 mm shallower than
// the truth and missed 47 ML's bleeding, so any student's chart against the
// examiner reads 2 mm more in all (both interdental, both deep) than against
// the truth; the misreading student (2 mm over at three sites) misses the
// target against the examiner as against the truth, the careful one meets it.
TEST(Calibration, AgainstAReferenceExaminerTheStudentReadsAsTheExaminerDiffers) {
  for (const std::string student : {"careful", "misreading"}) {
    AttemptOptions o;
    o.student = student;
    o.device = "student:" + student;
    o.cache_dir = Cache();
    const AttemptOutcome out = RunAttempt(
        fs::path(SULCUS_SOURCE_DIR) / "lessons" / "periodontal_calibration.yaml", o);
    const LessonResult& r = out.result;
    ASSERT_TRUE(r.reference_agreement) << student;
    const Agreement& truth = r.agreement;
    const Agreement& ref = *r.reference_agreement;
    EXPECT_EQ(ref.sites, 24) << student;
    EXPECT_EQ(truth.sites, 24) << student;
    EXPECT_NEAR(ref.all.sum_mm, truth.all.sum_mm + 2, 1e-9) << student;
    EXPECT_NEAR(ref.interdental.sum_mm, truth.interdental.sum_mm + 2, 1e-9) << student;
    EXPECT_NEAR(ref.mid.sum_mm, truth.mid.sum_mm, 1e-9) << student;
    EXPECT_EQ(ref.deep.sites, 7) << "the sites the examiner read 5 mm or more";
    ASSERT_TRUE(ref.bleeding_kappa) << student;
    EXPECT_LT(*ref.bleeding_kappa, 1.0) << "47 ML's bleeding the examiner missed";
    EXPECT_EQ(ref.MeetsTarget(), student == "careful") << student;
    const std::string html = ReportHtml(r, {});
    EXPECT_NE(html.find("Calibration against the reference examiner "
                        "(sextant_reference_examiner.yaml)"),
              std::string::npos);
    EXPECT_NE(html.find("charted minus the reference examiner"), std::string::npos);
    const std::string json = ReportJson(r, {});
    EXPECT_NE(json.find("\"reference_calibration\""), std::string::npos);
  }
}

TEST(Students, TheRoughOneFailsForceAndDamageAndBleedingIsFlagged) {
  const LessonResult r = Take("rough").result;
  // 2 N at every floor; a site's reading is the deepest dwell anywhere in its
  // zone, and at 44 DB that is in the interproximal area by 45, where the
  // gingiva's floor falls toward 45's deeper pocket, reached at 0.42 N: a
  // partial force line there.
  EXPECT_GE(Lines(r, "force", RubricLine::Status::kFail).size(), 23u)
      << "2 N at every floor";
  EXPECT_GE(Lines(r, "damage", RubricLine::Status::kFail).size(), 23u);
  // The floor is reached everywhere, and 2 N pushes the tip on through it:
  // every site reads deeper than its truth, as a forced probe over-reads.
  for (const SiteResult& s : r.sites) {
    ASSERT_TRUE(s.reached_mm) << s.site.ToString();
    EXPECT_GT(*s.reached_mm, s.truth_mm + 0.5) << s.site.ToString();
  }
  for (const RubricLine* l : Lines(r, "technique", RubricLine::Status::kFail))
    EXPECT_NE(l->message.find("pushed through the floor"), std::string::npos)
        << l->message;
  std::set<std::string> bled;
  for (const SiteResult& s : r.sites)
    if (s.bled) bled.insert(s.site.ToString());
  EXPECT_EQ(bled,
            (std::set<std::string>{"45 DB", "46 MB", "46 DB", "46 DL", "47 MB", "47 ML"}))
      << "the scene's";
  std::set<std::string> flagged;
  for (const RubricLine& l : r.lines)
    if (l.category == "bleeding" &&
        l.message.find("possibly caused by probing force") != std::string::npos)
      flagged.insert(l.site->ToString());
  EXPECT_EQ(flagged, bled);
  EXPECT_LT(r.total, 80.0);
}

// Students with human hands (scripted_student.h): each reads every site within
// 1 mm of the truth. The careful-but-human one (tremor, drift, slow strokes, an
// overshoot backed off, charting at rest) and the trembling one hold the force
// in the band at every site, and tremor does not multiply the readings.
int Insertions(const LessonResult& r) {
  int n = 0;
  for (const SiteResult& s : r.sites) n += s.insertions;
  return n;
}

TEST(HumanHands, EachReadsEverySiteWithinAMillimetre) {
  const LessonResult careful = Take("careful").result;
  std::printf("figure: careful %.1f, %d insertions\n", careful.total,
              Insertions(careful));
  for (const char* name : {"tremor", "slow", "hesitant", "overshoot", "occlusal",
                           "charting", "human", "keys"}) {
    const LessonResult r = Take(name).result;
    std::printf(
        "figure: %-9s %.1f / 100, %d of 24 read, force in band %.0f %%, %d insertions, "
        "%.1f s\n",
        name, r.total, r.sites_read, r.force_in_band_pct, Insertions(r), r.duration_s);
    EXPECT_EQ(r.sites_read, 24) << name;
    int beyond = 0;
    for (const SiteResult& s : r.sites) {
      ASSERT_TRUE(s.reached_mm)
          << name << " " << s.site.ToString() << ": " << s.no_reading;
      const double off = std::abs(*s.reached_mm - s.truth_mm);
      if (off > 1.0) {
        ++beyond;
        std::printf("figure: %-9s %s read %.1f mm off\n", name, s.site.ToString().c_str(),
                    *s.reached_mm - s.truth_mm);
      }
      EXPECT_LE(off, 1.5) << name << " " << s.site.ToString();
    }
    // Known: the careful-but-human hand's deepest stay at 47 MB, on its drifting
    // walk into the col by 46, is past the cut into 46's gingiva, where the
    // depth is read against 47's own floor there (4.6 mm, 6 at the line): one
    // site 1.4 mm short. Every other hand reads every site within 1 mm.
    EXPECT_LE(beyond, std::string(name) == "human" ? 1 : 0) << name;
    const std::string n = name;
    if (n == "human" || n == "tremor" || n == "overshoot" || n == "charting") {
      // The force held at the floor is in the band at (nearly) every site; the
      // highest tick, which the lesson once scored, is not.
      int held = 0, peak = 0;
      for (const SiteResult& s : r.sites) {
        held += s.held_force_n >= r.rubric.force_low_n &&
                s.held_force_n <= r.rubric.force_high_n;
        peak += s.peak_force_n >= r.rubric.force_low_n &&
                s.peak_force_n <= r.rubric.force_high_n;
      }
      std::printf(
          "figure: %-9s force in band at %d of 24 sites (held), %d (highest tick)\n",
          name, held, peak);
      EXPECT_GE(held, 22) << name;
      // Tremor does not multiply the readings: at most a quarter more visits than
      // the careful hand's (a slower, drifting hand revisits a few line angles;
      // the human hand's 58 became 61 of the careful hand's 50 when the engine
      // began to ease slips over the root's sphere bumps).
      EXPECT_LE(Insertions(r), Insertions(careful) * 5 / 4)
          << name << ": one dwell, one reading";
    }
    if (n == "overshoot") {
      int peaks_above = 0;
      for (const SiteResult& s : r.sites)
        peaks_above += s.peak_force_n > s.held_force_n + 0.05;
      EXPECT_GT(peaks_above, 12) << name << ": the overshoot is kept as the peak";
    }
    if (n == "charting" || n == "human") {
      // Charted with the probe at the floor: every entry made while reading.
      int at_rest = 0;
      for (const SiteResult& s : r.sites)
        at_rest += s.entry && s.entry->tick < r.last_tick;
      EXPECT_GE(at_rest, 12) << name << ": the sites charted at rest";
    }
  }
}

// A person's attempt, kept as a fixture: four sites probed in the window with
// the keys a student uses (N over the next site, R twelve times for a press of
// 0.24 N, the depth typed with the probe still at the floor, X), recorded by
// LessonWindow.APersonProbesFourSitesByKeysAndEachIsScored and compressed with
// xz. Replayed headless with its entries, every site probed is read within
// 1 mm of the truth with its held force in the band, once; every other site
// says why it has no reading.
TEST(PersonFixture, AnAttemptByKeysInTheWindowIsReadAtEverySiteItProbed) {
  const fs::path data = fs::path(SULCUS_TEST_DATA) / "person";
  const fs::path rec = Out("person_keys.rec");
  const std::string unpack = "xz -dc '" + (data / "keys_four_sites.rec.xz").string() +
                             "' > '" + rec.string() + "'";
  ASSERT_EQ(std::system(unpack.c_str()), 0) << unpack;
  AttemptOptions o;
  o.student = "Key Hand";
  o.device = "replay:" + rec.string();
  o.answers = data / "keys_four_sites_answers.yaml";
  o.cache_dir = Cache();
  o.mode = LessonSpec::Mode::kPractice;
  const LessonResult r = RunAttempt(Lesson(), o).result;
  const Answers a = LoadAnswers(o.answers);
  ASSERT_EQ(a.entries.size(), 4u);
  for (const SiteResult& s : r.sites) {
    const bool probed =
        std::any_of(a.entries.begin(), a.entries.end(),
                    [&](const ChartEntry& e) { return e.site == s.site; });
    if (!probed) {
      EXPECT_FALSE(s.reached_mm) << s.site.ToString();
      EXPECT_FALSE(s.no_reading.empty()) << s.site.ToString();
      continue;
    }
    ASSERT_TRUE(s.reached_mm) << s.site.ToString() << ": " << s.no_reading;
    std::printf(
        "figure: %s reached %.2f mm (truth %d), held %.3f N, peak %.3f N, %d "
        "insertion(s), charted %d\n",
        s.site.ToString().c_str(), *s.reached_mm, s.truth_mm, s.held_force_n,
        s.peak_force_n, s.insertions, s.entry ? s.entry->pd_mm.value_or(-1) : -1);
    EXPECT_LE(std::abs(*s.reached_mm - s.truth_mm), 1.0) << s.site.ToString();
    // The recording is the hand's poses, made on an earlier gingiva whose pocket
    // profile rose to each site more gently: the same hand meets the floor
    // sooner at some sites now, and holds more there. At 46 DB (a 7 mm pocket
    // beside a 6 mm one across the contact) the person held 0.24 N; the
    // gingiva built now takes the same pose at 0.71 N (0.38 N on the meshes
    // built before the lines' knots followed them; the tip's depth is the
    // same, 7.27 mm). Pressed to the floor; bounded; past the damage limit
    // only where the replayed pose no longer matches the floor.
    EXPECT_GE(s.held_force_n, r.rubric.force_low_n) << s.site.ToString();
    EXPECT_LE(s.peak_force_n, (s.site == SiteRef{46, 2} ? 1.0 : r.rubric.force_damage_n))
        << s.site.ToString();
    EXPECT_EQ(s.insertions, 1) << s.site.ToString();
  }
  EXPECT_EQ(r.sites_read, 4);
  EXPECT_EQ(r.sites_charted, 4);
  EXPECT_GE(r.force_in_band_pct, 50.0);
}

// The scripted "keys" student plays the window's keys (N, R, the walking keys,
// T) on the window's own device: every site read and charted, the col reached
// at every interdental site next to a contact, every surface's walk covered.
TEST(Students, TheKeysStudentUsesNTAndTheWalkingKeys) {
  const LessonResult r = Take("keys").result;
  std::printf("figure: keys %.1f / 100, %d of 24 read, %.1f s\n", r.total, r.sites_read,
              r.duration_s);
  EXPECT_EQ(r.sites_read, 24);
  EXPECT_EQ(r.sites_charted, 24);
  int contacts = 0;
  for (const SiteResult& s : r.sites) {
    if (!s.interproximal_contact) continue;
    ++contacts;
    EXPECT_TRUE(s.col_reached) << s.site.ToString();
  }
  EXPECT_EQ(contacts, 12) << "45, 46 and the neighbours' facing sites";
  EXPECT_TRUE(Lines(r, "coverage", RubricLine::Status::kFail).empty());
  EXPECT_GE(r.total, 98.0);
  EXPECT_TRUE(r.complete);
}

// Where people's hands go, not where N puts them: a tip resting at a line
// angle (1.1 mm along the sulcus from 47 DB's line toward 47 B), pressed to
// the floor, is read for 47 DB; then charted at rest, and a harder, deeper
// dwell after the entry in the same visit is not its reading.
TEST(Readings, ATipAtALineAngleIsReadAndADwellAfterChartingIsNot) {
  const LessonSpec spec = LoadLessonSpec(Lesson());
  const auto scene = CompileScene(LoadSceneSpec(spec.scene), Cache());
  const ProbingSite* db = nullptr;
  for (const ProbingSite& p : scene->effects.sites)
    if (p.fdi == 47 && p.site == 2) db = &p;
  ASSERT_TRUE(db && db->ring);
  const SulcusRing& ring = *db->ring;
  const Vector3 m = ring.ToRing(db->margin_W);
  const double phi = std::atan2(m.y(), m.x());
  const double toward_b =
      std::remainder(std::numbers::pi / 2 - phi, 2 * std::numbers::pi) > 0 ? 1.0 : -1.0;
  const double at = phi + toward_b * 1.1 / std::hypot(m.x(), m.y());
  const int k = ring.SegmentAt(at);
  const double floor = ring.margin_z[static_cast<std::size_t>(k)] -
                       ring.floor_z[static_cast<std::size_t>(k)];
  const Quaternion q = Quaternion::FromTwoVectors(Vector3::UnitZ(), ring.AxisW());
  std::vector<Keyframe> keys = {
      {0.0, ring.PointAt(at, -6.0), q},         {0.5, ring.PointAt(at, -0.5), q},
      {1.0, ring.PointAt(at, floor - 0.4), q},  {1.3, ring.PointAt(at, floor + 0.1), q},
      {2.3, ring.PointAt(at, floor + 0.1), q},   // resting at the floor
      {2.6, ring.PointAt(at, floor + 0.35), q},  // harder and deeper, after charting
      {3.6, ring.PointAt(at, floor + 0.35), q}, {4.2, ring.PointAt(at, -3.0), q}};
  LessonRun lesson(spec, *scene, "line angle");
  DeviceSpec d;
  d.device = std::make_unique<ScriptedDevice>(Trajectory(std::move(keys)), "line angle");
  SessionOptions so;
  so.max_ticks = 4400;
  Session session(*scene, std::move(d), so);
  session.AddConsumer(&lesson);
  struct Charter final : TickConsumer {
    LessonRun* lesson;
    bool charted = false;
    std::optional<SiteRef> seen;
    void OnTick(const TickRecord& r) override {
      if (lesson->tip_site()) seen = lesson->tip_site();
      if (!charted && r.time_s >= 2.2 && lesson->tip_site() && lesson->tip_depth_mm()) {
        ChartEntry e;
        e.site = *lesson->tip_site();
        e.tick = r.tick + 1;
        e.pd_mm = static_cast<int>(std::lround(*lesson->tip_depth_mm()));
        lesson->Enter(e);
        charted = true;
      }
    }
  } charter;
  charter.lesson = &lesson;
  session.AddConsumer(&charter);
  session.RunOffline();
  lesson.OnEnd();
  ASSERT_TRUE(charter.charted);
  const LessonResult r = lesson.Finish();
  for (const SiteResult& s : r.sites) {
    if (s.site != SiteRef{47, 2}) {
      if (s.site.fdi == 47 && s.site.site == 1) {
        EXPECT_FALSE(s.reached_mm) << "47 B: the tip was in 47 DB's zone";
      }
      continue;
    }
    ASSERT_TRUE(s.reached_mm) << s.no_reading;
    ASSERT_TRUE(s.entry && s.entry->pd_mm);
    std::printf(
        "figure: 47 DB at its line angle: reached %.2f mm, held %.3f N, charted %d\n",
        *s.reached_mm, s.held_force_n, *s.entry->pd_mm);
    EXPECT_LE(std::abs(*s.reached_mm - s.truth_mm), 1.0);
    EXPECT_LE(s.reading_tick, s.entry->tick) << "the reading is the charted one";
    EXPECT_LT(*s.reached_mm, floor + 0.3) << "not the dwell 0.35 mm past the floor";
  }
}

// Next moves on only after a reading at the floor, or when the student moves
// on: a touch 1 mm into the first site leaves Next there; pressed to the floor,
// Next goes to the second; a touch at the third (the second skipped) takes Next
// to the third, and once the third is read on to the fourth (the second comes
// round when the path does).
TEST(LessonRun, NextMovesOnAfterAReadingAtTheFloorOrWhenTheStudentMovesOn) {
  const LessonSpec spec = LoadLessonSpec(Lesson());
  const auto scene = CompileScene(LoadSceneSpec(spec.scene), Cache());
  LessonRun lesson(spec, *scene, "next");
  ASSERT_GE(lesson.sites().size(), 3u);
  const SiteRef first = lesson.sites()[0].site, second = lesson.sites()[1].site,
                third = lesson.sites()[2].site;
  // Down a site's own line to `depth` below the margin (past the floor: pressed).
  struct Stroke {
    SiteRef site;
    double below_floor;  // < 0: above the floor by that much
  };
  double t = 0;
  std::vector<Keyframe> keys;
  std::vector<double> ends;
  for (const Stroke& st : {Stroke{first, -2.0}, Stroke{first, 0.1}, Stroke{third, -2.0},
                           Stroke{third, 0.1}}) {
    const ProbingSite* p = nullptr;
    for (const ProbingSite& x : scene->effects.sites)
      if (x.fdi == st.site.fdi && x.site == st.site.site) p = &x;
    ASSERT_TRUE(p && p->ring) << st.site.ToString();
    const SulcusRing& ring = *p->ring;
    const Vector3 m = ring.ToRing(p->margin_W);
    const double phi = std::atan2(m.y(), m.x());
    const auto k = static_cast<std::size_t>(ring.SegmentAt(phi));
    const double depth = ring.margin_z[k] - ring.floor_z[k] + st.below_floor;
    const Quaternion q = Quaternion::FromTwoVectors(Vector3::UnitZ(), ring.AxisW());
    for (const auto& [dt, d] :
         {std::pair{0.0, -4.0}, std::pair{0.5, -0.5}, std::pair{1.2, depth},
          std::pair{2.2, depth}, std::pair{2.8, -4.0}})
      keys.push_back({t + dt, ring.PointAt(phi, d), q});
    t += 3.0;
    ends.push_back(t);
  }
  keys.push_back({t + 0.5, keys.back().p_W, keys.back().q_W});  // held, for the last look
  DeviceSpec d;
  d.device = std::make_unique<ScriptedDevice>(Trajectory(std::move(keys)), "next");
  SessionOptions so;
  so.max_ticks = static_cast<std::uint64_t>((t + 0.5) * scene->spec.rate_hz);
  Session session(*scene, std::move(d), so);
  session.AddConsumer(&lesson);
  struct Watch final : TickConsumer {
    LessonRun* lesson;
    std::vector<double> at;
    std::vector<std::string> next;
    void OnTick(const TickRecord& r) override {
      if (next.size() < at.size() && r.time_s >= at[next.size()] - 0.05) {
        const std::optional<SiteRef> n = lesson->next_site();
        next.push_back(n ? n->ToString() : "none");
      }
    }
  } watch;
  watch.lesson = &lesson;
  watch.at = ends;
  session.AddConsumer(&watch);
  session.RunOffline();
  ASSERT_EQ(watch.next.size(), 4u);
  EXPECT_EQ(watch.next[0], first.ToString()) << "a touch 2 mm short of the floor";
  EXPECT_EQ(watch.next[1], second.ToString()) << "read at the floor";
  EXPECT_EQ(watch.next[2], third.ToString()) << "the student moved on to the third";
  EXPECT_EQ(watch.next[3], lesson.sites()[3].site.ToString())
      << "on along the path from the third (the skipped second comes round at the end)";
  EXPECT_FALSE(LessonRun::ReadAtFloor(lesson.sites()[1]));
}

TEST(Students, TheMisreadingOneFailsReadingAtExactlyItsThreeSites) {
  const LessonSpec spec = LoadLessonSpec(Lesson());
  std::set<std::string> expected;
  {
    const auto scene = CompileScene(LoadSceneSpec(spec.scene), Cache());
    const ScriptedStudent student("misreading", spec, *scene);
    for (const SiteRef& s : student.misread_sites()) expected.insert(s.ToString());
  }
  EXPECT_EQ(expected, (std::set<std::string>{"47 DB", "46 DB", "45 DB"}));
  const LessonResult r = Take("misreading").result;
  EXPECT_EQ(Sites(Lines(r, "reading", RubricLine::Status::kFail)), expected);
  EXPECT_EQ(Lines(r, "reading", RubricLine::Status::kPass).size(), 21u);
  EXPECT_TRUE(Lines(r, "technique", RubricLine::Status::kFail).empty())
      << "the technique was right";
  EXPECT_TRUE(Lines(r, "technique", RubricLine::Status::kPartial).empty());
  EXPECT_EQ(Sites(Lines(r, "charting", RubricLine::Status::kFail)), expected);
  // Its calibration shows the examiner it is: 2 mm over at three interdental
  // sites, right at the mid-sites, short of the target; the careful one on it.
  const Agreement& g = r.agreement;
  EXPECT_EQ(g.sites, 24);
  EXPECT_NEAR(g.within_1mm_pct, 100.0 * 21 / 24, 1e-9);
  ASSERT_TRUE(g.interdental.mean_mm() && g.mid.mean_mm());
  EXPECT_NEAR(*g.interdental.mean_mm(), 6.0 / 16, 1e-12);
  EXPECT_EQ(*g.mid.mean_mm(), 0.0);
  ASSERT_TRUE(g.depth_kappa);
  EXPECT_LT(*g.depth_kappa, 0.95);
  EXPECT_FALSE(g.MeetsTarget());
  const Agreement careful = Take("careful").result.agreement;
  ASSERT_TRUE(careful.depth_kappa);
  EXPECT_DOUBLE_EQ(*careful.depth_kappa, 1.0);
  EXPECT_TRUE(careful.MeetsTarget());
}

TEST(Students, TheSpotProberFailsCoverageOnEverySurface) {
  const LessonResult r = Take("spot").result;
  ASSERT_EQ(r.coverage.size(), 8u);
  for (const SurfaceCoverage& c : r.coverage)
    EXPECT_LT(c.swept, 0.3) << c.fdi << (c.buccal ? " buccal" : " lingual");
  EXPECT_EQ(Lines(r, "coverage", RubricLine::Status::kFail).size(), 8u);
  EXPECT_NE(
      Lines(r, "coverage", RubricLine::Status::kFail)[0]->message.find("spot-probing"),
      std::string::npos);
}

TEST(Students, TheLazyOneSkipsATeethAndCompletenessSaysWhich) {
  const LessonResult r = Take("lazy").result;
  // It never probes 46; its strokes into the cols on either side of 46 can
  // come down nearer 46's sulcus than its neighbour's, and the one locator
  // reads such a stroke for 46's facing site (46 MB here, stopped short): at
  // most one 46 site read, in path order the rest are the unprobed ones.
  std::vector<std::string> unprobed_order;
  for (const SiteResult& s : r.sites)
    if (!s.reached_mm) unprobed_order.push_back(s.site.ToString());
  for (const std::string& u : unprobed_order) EXPECT_EQ(u.substr(0, 2), "46") << u;
  EXPECT_GE(unprobed_order.size(), 5u);
  EXPECT_EQ(r.sites_read, 24 - static_cast<int>(unprobed_order.size()));
  const std::set<std::string> unprobed(unprobed_order.begin(), unprobed_order.end());
  const auto incomplete = Lines(r, "completeness", RubricLine::Status::kFail);
  ASSERT_EQ(incomplete.size(), 2u);
  EXPECT_EQ(incomplete[0]->message,
            std::to_string(r.sites_read) +
                " of 24 sites probed; not probed: " + Join(unprobed_order));
  std::set<std::string> not_probed;
  for (const RubricLine* l : Lines(r, "technique", RubricLine::Status::kFail))
    if (l->message.find("not probed") != std::string::npos)
      not_probed.insert(l->site->ToString());
  EXPECT_EQ(not_probed, unprobed);
  EXPECT_FALSE(r.steps[0].completed);
  // A blank site scores as a wrong depth on the charting line (0 credit), below
  // a depth 1 mm off (0.5): leaving an uncertain site blank does not pay.
  std::set<std::string> blank;
  for (const RubricLine* l : Lines(r, "charting", RubricLine::Status::kFail))
    if (l->message.find("not charted") != std::string::npos) {
      EXPECT_EQ(l->credit, 0);
      blank.insert(l->site->ToString());
    }
  EXPECT_EQ(blank, unprobed);
  // Its reading lines fail there too: no reading was entered.
  std::set<std::string> unread;
  for (const RubricLine* l : Lines(r, "reading", RubricLine::Status::kFail))
    if (l->message.find("no reading entered") != std::string::npos) {
      EXPECT_EQ(l->credit, 0);
      unread.insert(l->site->ToString());
    }
  EXPECT_EQ(unread, blank);
  std::printf("figure: lazy %.1f / 100 (46 left blank)\n", r.total);
}

// The same hand, the same readings: an uncertain site charted 1 mm off scores
// more than the site left blank, on the reading and charting lines and in all.
TEST(Students, ABlankSiteIsNeverBetterThanAnHonestAttempt) {
  const LessonSpec spec = LoadLessonSpec(Lesson());
  const PerioChart truth = TrueChart(LoadSceneSpec(spec.scene), spec.teeth);
  // Every site as it truly is, but 46 DB (7 mm) charted 6, or left blank.
  auto answers = [&](const std::string& name, bool blank) {
    std::string text = "entries:\n";
    for (const SiteRef& site : spec.path) {
      const SiteValues& v = truth.Find(site.fdi)->sites[site.site];
      int pd = *v.pd_mm;
      if (site.ToString() == "46 DB") {
        if (blank) continue;
        pd -= 1;
      }
      text += "  - {site: \"" + site.ToString() + "\", pd: " + std::to_string(pd) +
              (v.bleeding ? ", bleeding: true" : "") + "}\n";
    }
    return test::WriteText(Out(name), text);
  };
  auto take = [&](const fs::path& file) {
    AttemptOptions o;
    o.device = "student:careful";
    o.cache_dir = Cache();
    o.answers = file;
    return RunAttempt(Lesson(), o).result;
  };
  const LessonResult off = take(answers("off_by_one.yaml", false));
  const LessonResult left = take(answers("left_blank.yaml", true));
  EXPECT_EQ(off.sites_charted, 24);
  EXPECT_EQ(left.sites_charted, 23);
  for (const char* category : {"reading", "charting"}) {
    ASSERT_TRUE(off.category_credit.count(category) &&
                left.category_credit.count(category));
    EXPECT_GT(off.category_credit.at(category), left.category_credit.at(category))
        << category;
  }
  EXPECT_GT(off.total, left.total);
  std::printf("figure: 46 DB charted 1 mm off %.2f, left blank %.2f\n", off.total,
              left.total);
}

TEST(Replay, ARecordedAttemptGivesTheSameReport) {
  const fs::path rec = Out("careful.rec");
  const AttemptOutcome first = Take("careful", rec);
  SaveAnswers(first.answers, Out("careful_answers.yaml"));
  AttemptOptions o;
  o.student = "careful";
  o.device = "replay:" + rec.string();
  o.answers = Out("careful_answers.yaml");
  o.cache_dir = Cache();
  const AttemptOutcome again = RunAttempt(Lesson(), o);
  ReportInfo info;
  info.started = "2026-01-01T00:00:00Z";
  EXPECT_EQ(ReportJson(again.result, info), ReportJson(first.result, info))
      << "the same report, byte for byte";
  EXPECT_EQ(again.result.total, first.result.total);

  // The JSON is well formed and says what the result says.
  const YAML::Node j = YAML::Load(ReportJson(first.result, info));
  EXPECT_EQ(j["lesson"].as<std::string>(), "Periodontal probing, lower right sextant");
  EXPECT_EQ(j["sites"].size(), 24u);
  EXPECT_EQ(j["lines"].size(), first.result.lines.size());
  EXPECT_EQ(j["diagnosis"]["truth"]["stage"].as<std::string>(), "III");
  const std::string html = ReportHtml(first.result, info);
  for (const char* part :
       {"<table class=chart>", "Error map", "Force at each site", "Walking stroke",
        "Every line of the score", "periodontitis stage III, localized", "<svg"})
    EXPECT_NE(html.find(part), std::string::npos) << part;
  WriteReport(first.result, info, Out("report"));
  EXPECT_TRUE(fs::exists(Out("report") / "report.html"));
}

TEST(GeneratedCase, AnAssessmentOnADrawnCaseStoresItsSeedAndRebuilds) {
  const fs::path lesson =
      fs::path(SULCUS_SOURCE_DIR) / "lessons" / "periodontal_probing_case.yaml";
  AttemptOptions o;
  o.device = "student:careful";
  o.seed = 7;
  o.cache_dir = Cache();
  o.record = Out("case.rec");
  const AttemptOutcome out = RunAttempt(lesson, o);
  EXPECT_EQ(out.seed, 7u);
  EXPECT_TRUE(out.result.generated_case);
  EXPECT_EQ(out.result.case_seed, 7u);
  EXPECT_EQ(out.result.mode, "assessment");
  EXPECT_EQ(out.result.true_dx.Summary(), "periodontitis stage III, localized");
  for (const std::string& f : out.result.feedback)
    EXPECT_EQ(f.find("true depth"), std::string::npos) << f;
  EXPECT_GE(out.result.total, 90.0);
  // A lesson's recording is compact (docs/recordings.md): at most 30 bytes a tick.
  const Recording rec = ReadRecording(Out("case.rec"));
  ASSERT_GT(rec.frames.size(), 100000u);
  const double per_tick = static_cast<double>(rec.file_bytes) / rec.frames.size();
  std::printf("figure: the careful student's recording: %zu ticks, %.1f bytes a tick\n",
              rec.frames.size(), per_tick);
  EXPECT_LE(per_tick, 30.0);
  // The same seed and recording rebuild the same result.
  SaveAnswers(out.answers, Out("case_answers.yaml"));
  o.device = "replay:" + Out("case.rec").string();
  o.answers = Out("case_answers.yaml");
  o.record.clear();
  const AttemptOutcome again = RunAttempt(lesson, o);
  EXPECT_EQ(ReportJson(again.result, {}), ReportJson(out.result, {}));
}

// A case rebuilds only what its pockets change (the gingiva, at the case's
// resolution, and the bone where its crest moved), and the case saved as a
// scene of its own opens from the trees its lesson built.
TEST(GeneratedCase, OnlyTheGingivaIsRebuiltAndASavedCaseOpensFromTheCache) {
  const fs::path lesson_file =
      fs::path(SULCUS_SOURCE_DIR) / "lessons" / "periodontal_probing_case.yaml";
  const LessonSpec spec = LoadLessonSpec(lesson_file);
  const fs::path cache = Out("case-cache");
  fs::remove_all(cache);
  // A first case builds everything; the next rebuilds only what changed.
  const auto first = CompileScene(LessonScene(spec, 4243), cache);
  EXPECT_TRUE(first->tree_built[0]) << "a fresh cache";
  const auto drawn = CompileScene(LessonScene(spec, 4242), cache);
  int gingiva = 0;
  for (std::size_t i = 0; i < drawn->spec.objects.size(); ++i) {
    const ObjectSpec& o = drawn->spec.objects[i];
    if (o.kind == ObjectSpec::Kind::kGingiva) {
      ++gingiva;
      EXPECT_TRUE(drawn->tree_built[i]) << o.name << ": its pockets changed";
      EXPECT_EQ(drawn->trees[i].NumLeaves(), static_cast<std::size_t>(kCaseGingivaLeaves))
          << o.name;
      EXPECT_EQ(o.trees.spend, SphereTreeParams::Spend::kWorst) << o.name;
      EXPECT_EQ(o.trees.tighten_passes, kCaseGingivaTightenPasses) << o.name;
    } else if (o.kind == ObjectSpec::Kind::kTooth) {
      EXPECT_FALSE(drawn->tree_built[i]) << o.name << ": a tooth is the scene's";
    }
  }
  EXPECT_EQ(gingiva, 4);
  // Saved, and opened as a scene: nothing is built.
  const fs::path saved = Out("case-4242.yaml");
  fs::remove(saved);
  const SceneSpec back = SaveCaseScene(spec, spec.case_spec, 4242, saved);
  std::ifstream saved_in(saved);
  const std::string text((std::istreambuf_iterator<char>(saved_in)), {});
  EXPECT_NE(text.find("gingiva: {levels: 5, branch: 8, leaves: 1024, spend: worst, "
                      "tighten_passes: 1}"),
            std::string::npos)
      << text;
  const auto opened = CompileScene(back, cache);
  for (std::size_t i = 0; i < opened->spec.objects.size(); ++i) {
    EXPECT_FALSE(opened->tree_built[i]) << opened->spec.objects[i].name;
    EXPECT_EQ(opened->trees[i].r, drawn->trees[i].r) << opened->spec.objects[i].name;
  }
}

}  // namespace
}  // namespace sulcus
