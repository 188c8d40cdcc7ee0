// The oral inspection lesson: its file, the odontogram and its answers, the
// scene's truth, and scripted inspectors with known answers taking it on the
// full mouth.

#include "core/lesson/inspection.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/collision/collision.h"
#include "core/haptics/scripted_device.h"
#include "core/lesson/attempt.h"
#include "core/lesson/report.h"
#include "core/lesson/scripted_inspector.h"
#include "core/scene/scene.h"
#include "core/spheretree/cache.h"
#include "tests/common/load_errors.h"
#include "tests/common/output.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

fs::path Lesson() {
  return fs::path(SULCUS_SOURCE_DIR) / "lessons" / "oral_inspection.yaml";
}
fs::path Out(const std::string& name) { return test::OutputPath("inspection", name); }
fs::path Write(const std::string& name, const std::string& text) {
  return test::WriteText(Out(name), text);
}

std::vector<std::string> Errors(const fs::path& file, bool answers = false) {
  return test::ErrorLines([&] {
    if (answers)
      LoadAnswers(file);
    else
      LoadLessonSpec(file);
  });
}

bool AnyContains(const std::vector<std::string>& v, const std::string& what) {
  return std::any_of(v.begin(), v.end(), [&](const std::string& s) {
    return s.find(what) != std::string::npos;
  });
}

TEST(InspectionLesson, TheShippedLessonIsValid) {
  const LessonSpec spec = LoadLessonSpec(Lesson());
  EXPECT_TRUE(spec.inspection());
  EXPECT_EQ(spec.teeth.size(), 28u);
  EXPECT_EQ(spec.regions.size(), InspectionRegionNames().size())
      << "the scene has every region";
  ASSERT_EQ(spec.steps.size(), 11u);
  EXPECT_EQ(spec.steps[1].regions,
            (std::vector<std::string>{"cheek_right", "cheek_left"}));
  EXPECT_EQ(spec.steps.back().complete, StepSpec::Complete::kRecorded);
  EXPECT_TRUE(spec.path.empty()) << "an inspection has no probing path";
}

TEST(InspectionLesson, EveryErrorAtOnceWithItsPlace) {
  const fs::path f = Write(
      "bad_inspection.yaml",
      "kind: inspection\n"
      "scene: " +
          (fs::path(SULCUS_SOURCE_DIR) / "scenes" / "oral_inspection.yaml").string() +
          "\n"
          "path: standard\n"
          "steps:\n"
          "  - instruction: lips\n"
          "    complete: read\n"
          "    regions: [lip_uper]\n"
          "  - instruction: teeth\n"
          "    complete: touched\n"
          "    teeth: [36]\n"
          "    surfaces: [B, X]\n"
          "  - instruction: nothing named\n"
          "    complete: touched\n");
  const auto e = Errors(f);
  EXPECT_TRUE(AnyContains(e, ":3:1: unknown key 'path'")) << ::testing::PrintToString(e);
  EXPECT_TRUE(AnyContains(e, ":6:15: unknown completion 'read' for an inspection lesson"))
      << ::testing::PrintToString(e);
  EXPECT_TRUE(
      AnyContains(e, ":7:15: unknown region 'lip_uper'; did you mean 'lip_upper'?"))
      << ::testing::PrintToString(e);
  EXPECT_TRUE(AnyContains(e, ":11:19: unknown surface 'X'"))
      << ::testing::PrintToString(e);
  EXPECT_TRUE(AnyContains(e, ":12:5: a 'touched' step names what it examines"))
      << ::testing::PrintToString(e);
}

TEST(Odontogram, FindingsReadAndWriteBackAndBadOnesAreNamed) {
  const fs::path f = Write(
      "findings.yaml",
      "findings:\n"
      "  - {tooth: 36, caries: [O, B], tick: 10}\n"
      "  - {tooth: 16, calculus: true}\n"
      "  - {tooth: 31, inflamed: true, tick: 20}\n"
      "  - {tooth: 24, status: 3}\n"
      "  - {region: tongue_lateral_border_left, lesion: ulcer, tick: 30}\n"
      "  - {tooth: 36, caries: B, present: false, tick: 40}\n"
      "submitted: 50\n"
      "views:\n"
      "  - {tick: 12, eye: [0, 60, 10], at: [0, -20, 10], up: [0, 0, 1], angle: 30}\n");
  const Answers a = LoadAnswers(f);
  ASSERT_EQ(a.findings.size(), 7u);
  EXPECT_EQ(a.findings[1].surface, ToothSurface::kBuccal);
  EXPECT_EQ(a.findings[1].tick, 10u);
  EXPECT_EQ(a.findings[2].tick, kAfterReading);
  EXPECT_FALSE(a.findings[6].present);
  ASSERT_TRUE(a.submitted);
  EXPECT_EQ(*a.submitted, 50u);
  Odontogram o = EmptyOdontogram({16, 24, 31, 36});
  for (const Finding& x : a.findings) o.Apply(x);
  EXPECT_TRUE(o.Find(36)->caries[static_cast<int>(ToothSurface::kOcclusal)]);
  EXPECT_FALSE(o.Find(36)->caries[static_cast<int>(ToothSurface::kBuccal)])
      << "withdrawn";
  EXPECT_EQ(o.Find(36)->Status(), 1) << "decayed, from its caries";
  EXPECT_EQ(o.Find(24)->Status(), 3);
  EXPECT_EQ(o.lesions.at("tongue_lateral_border_left"), "ulcer");
  // Written and read back: the same findings.
  const fs::path back = Out("findings_back.yaml");
  SaveAnswers(a, back);
  const Answers b = LoadAnswers(back);
  ASSERT_EQ(b.findings.size(), a.findings.size());
  for (std::size_t i = 0; i < a.findings.size(); ++i)
    EXPECT_EQ(b.findings[i].ToString(), a.findings[i].ToString()) << i;
  EXPECT_EQ(b.submitted, a.submitted);
  ASSERT_EQ(b.views.size(), 1u);
  EXPECT_EQ(b.views[0].tick, 12u);
  EXPECT_EQ(b.views[0].eye, Vector3(0, 60, 10));
  EXPECT_EQ(b.views[0].focal, Vector3(0, -20, 10));

  const auto e = Errors(Write("bad_findings.yaml",
                              "findings:\n"
                              "  - {tooth: 36, caries: Q}\n"
                              "  - {region: tonge_dorsum, lesion: ulcer}\n"
                              "  - {tooth: 36}\n"
                              "  - {region: palate, lesion: wart}\n"),
                        true);
  EXPECT_TRUE(AnyContains(e, ":2:25: unknown surface 'Q'"))
      << ::testing::PrintToString(e);
  EXPECT_TRUE(AnyContains(e, ":3:14: unknown region 'tonge_dorsum'"))
      << ::testing::PrintToString(e);
  EXPECT_TRUE(AnyContains(e, ":4:5: a finding is one of")) << ::testing::PrintToString(e);
  EXPECT_TRUE(AnyContains(e, ":5:30: unknown lesion 'wart'"))
      << ::testing::PrintToString(e);
}

TEST(Odontogram, TheScenesTruth) {
  const LessonSpec spec = LoadLessonSpec(Lesson());
  const SceneSpec scene = LoadSceneSpec(spec.scene);
  const Odontogram t = TrueOdontogram(scene, spec.teeth, spec.regions);
  std::set<std::string> caries, calculus, inflamed;
  for (const ToothRecord& r : t.teeth) {
    for (int s = 0; s < 5; ++s)
      if (r.caries[static_cast<std::size_t>(s)])
        caries.insert(std::to_string(r.fdi) + " " +
                      SurfaceCode(static_cast<ToothSurface>(s)));
    if (r.calculus) calculus.insert(std::to_string(r.fdi));
    if (r.inflamed) inflamed.insert(std::to_string(r.fdi));
  }
  EXPECT_EQ(caries, (std::set<std::string>{"16 O", "26 M", "36 B", "36 O", "45 D"}));
  EXPECT_EQ(calculus, (std::set<std::string>{"16", "31", "41", "46"}));
  EXPECT_EQ(inflamed, (std::set<std::string>{"31", "32", "46"}));
  EXPECT_EQ(
      t.lesions,
      (std::map<std::string, std::string>{{"tongue_lateral_border_left", "ulcer"}}));
}

// One attempt per scripted inspector, taken once and shared.
const AttemptOutcome& Take(const std::string& who) {
  static std::map<std::string, AttemptOutcome> done;
  auto it = done.find(who);
  if (it == done.end()) {
    AttemptOptions o;
    o.student = who;
    o.device = "student:" + who;
    o.cache_dir = DefaultCacheDir();  // the full mouth, shared with the window and the
                                      // probing tests
    it = done.emplace(who, RunAttempt(Lesson(), o)).first;
    WriteReport(it->second.result, {}, Out("report-" + who));
  }
  return it->second;
}

std::set<std::string> NotExamined(const LessonResult& r) {
  std::set<std::string> s;
  for (const InspectionUnit& u : r.inspection.units)
    if (!u.touched) s.insert(u.Name());
  return s;
}

const FindingScore& Score(const LessonResult& r, const std::string& kind) {
  for (const FindingScore& s : r.inspection.scores)
    if (s.kind == kind) return s;
  throw std::runtime_error("no score for " + kind);
}

std::vector<std::string> Messages(const LessonResult& r, const std::string& category,
                                  RubricLine::Status st) {
  std::vector<std::string> v;
  for (const RubricLine& l : r.lines)
    if (l.category == category && l.status == st) v.push_back(l.message);
  return v;
}

TEST(Inspectors, TheThoroughOneFindsEverythingItExamines) {
  const LessonResult& r = Take("thorough").result;
  EXPECT_EQ(r.kind, "inspection");
  std::size_t examined = 0;
  for (const InspectionUnit& u : r.inspection.units) examined += u.touched;
  EXPECT_GE(examined * 100, r.inspection.units.size() * 95)
      << "nearly every region and surface: " << examined << " of "
      << r.inspection.units.size();
  // A gentle hand that plans its way: no tissue pressed above its limit, and
  // a near-full score (what it still misses is a proximal surface or two where
  // the neighbour is in the way).
  EXPECT_TRUE(Messages(r, "damage", RubricLine::Status::kFail).empty())
      << ::testing::PrintToString(Messages(r, "damage", RubricLine::Status::kFail));
  EXPECT_GE(r.total, 90.0);
  // Every region: the gingiva and ridge of both arches too (their targets lie
  // on the arch's gingiva, which ends above where a collar did).
  const std::set<std::string> missed = NotExamined(r);
  for (const char* region :
       {"gingiva_upper", "gingiva_lower", "lip_upper", "lip_lower", "cheek_right",
        "cheek_left", "tongue_dorsum", "floor_of_mouth", "palate", "soft_palate"})
    EXPECT_FALSE(missed.count(region)) << region;
  // Every finding it recorded is true (specificity 1 for every kind), and it
  // found every finding on a surface or region it examined.
  for (const FindingScore& s : r.inspection.scores) EXPECT_EQ(s.fp, 0) << s.kind;
  EXPECT_EQ(Score(r, "lesion").tp, 1) << "the ulcer on the tongue's left lateral border";
  EXPECT_EQ(Score(r, "calculus").fn, 0);
  EXPECT_EQ(Score(r, "inflamed gingiva").fn, 0);
  EXPECT_TRUE(r.inspection.submitted_tick.has_value());
  EXPECT_TRUE(r.complete) << "submitting ends the examination: the steps still open are "
                             "left, with what they missed";
  bool told = false;
  for (const std::string& f : r.feedback)
    told |= f.find("36 O: a carious lesion here") != std::string::npos;
  EXPECT_TRUE(told) << "practice: the truth as each surface is examined";
  EXPECT_EQ(Score(r, "caries").fn, 0) << "every carious surface examined and found";
  // Every coverage line names its moment and the truth is in the result.
  for (const RubricLine& l : r.lines) EXPECT_LE(l.tick, r.last_tick) << l.message;
  EXPECT_FALSE(r.inspection.truth.teeth.empty());
}

// What the view showed: a camera in front of 36's buccal surface shows that
// surface (the cheek between is retracted, as the window draws it) and not its
// lingual one (it faces away); seen along the arch from behind 37, 36's distal
// surface is hidden by 37 until the camera comes round it. The report says
// which surfaces and regions were never in view once views are recorded.
TEST(Inspectors, TheViewShowsWhatFacesTheCameraAndNoNeighbourHides) {
  const AttemptOutcome& t = Take("thorough");
  const CompiledScene& scene = *t.scene;
  LessonRun run(t.spec, scene, "viewer");
  const InspectionTracker& tracker = *run.inspection();
  const int b = tracker.UnitOf(36, ToothSurface::kBuccal),
            l = tracker.UnitOf(36, ToothSurface::kLingual),
            d = tracker.UnitOf(36, ToothSurface::kDistal);
  ASSERT_GE(b, 0);
  ASSERT_GE(l, 0);
  ASSERT_GE(d, 0);
  const auto& unit = [&](int u) -> const InspectionUnit& {
    return tracker.units()[static_cast<std::size_t>(u)];
  };
  const auto spot = ApproachOf(scene, unit(b), t.spec.teeth),
             distal = ApproachOf(scene, unit(d), t.spec.teeth);
  ASSERT_TRUE(spot);
  ASSERT_TRUE(distal);
  auto look = [&](std::uint64_t tick, const Vector3& focal, const Vector3& eye) {
    ViewSample v;
    v.tick = tick;
    v.focal = focal;
    v.eye = eye;
    v.view_angle_deg = 30;
    run.View(v);
  };
  // Behind 37, looking forward along the arch at 36's distal spot.
  auto centre = [&](int fdi) {
    for (const ObjectSpec& o : scene.spec.objects)
      if (o.kind == ObjectSpec::Kind::kTooth && o.fdi == fdi)
        return Vector3(o.X_WO.translation());
    return Vector3(Vector3::Zero());
  };
  Vector3 from_behind =
      centre(37) + (centre(37) - centre(36));  // one tooth behind 37, on the arch
  from_behind.z() = distal->p.z();
  ASSERT_GT(distal->n.dot(from_behind - distal->p), 0) << "the spot faces that way";
  look(3, distal->p, from_behind);
  EXPECT_FALSE(unit(d).seen) << "37 lies between";
  look(4, distal->p, distal->p + 3.0 * distal->n);  // beside it
  EXPECT_TRUE(unit(d).seen);
  EXPECT_EQ(unit(d).seen_tick, 4u);
  look(5, spot->p, spot->p + 40.0 * spot->n);  // from outside the cheek
  EXPECT_TRUE(unit(b).seen) << "the cheek is retracted";
  EXPECT_FALSE(unit(l).seen) << "it faces away";
  EXPECT_FALSE(unit(tracker.UnitOf("palate")).seen) << "outside the view";
  const LessonResult r = run.Finish();
  const auto lines = Messages(r, "coverage", RubricLine::Status::kFail);
  EXPECT_TRUE(AnyContains(lines, "the hard palate: not examined; never in view"))
      << ::testing::PrintToString(lines);
  EXPECT_FALSE(AnyContains(Messages(r, "coverage", RubricLine::Status::kInfo),
                           "no view was recorded"));
  EXPECT_TRUE(AnyContains(
      Messages(Take("thorough").result, "coverage", RubricLine::Status::kInfo),
      "no view was recorded"));
}

// An inspection is rebuilt from its recording and its answers (findings,
// submission, views) to the same result, line for line: nothing is lost.
TEST(Inspectors, ARecordedInspectionRebuildsToTheSameResult) {
  AttemptOptions o;
  o.student = "recorded";
  o.device = "student:mistaken";
  o.cache_dir = DefaultCacheDir();
  o.record = Out("mistaken.rec");
  const AttemptOutcome first = RunAttempt(Lesson(), o);
  Answers answers = first.answers;
  ViewSample v;  // as the window would add
  v.tick = 100;
  v.eye = Vector3(0, 80, 12);
  v.focal = Vector3(0, -20, 12);
  answers.views.push_back(v);
  SaveAnswers(answers, Out("mistaken_answers.yaml"));
  AttemptOptions again;
  again.student = "recorded";
  again.device = "replay:" + Out("mistaken.rec").string();
  again.answers = Out("mistaken_answers.yaml");
  again.cache_dir = DefaultCacheDir();
  const AttemptOutcome second = RunAttempt(Lesson(), again);
  const LessonResult &a = first.result, &b = second.result;
  EXPECT_EQ(b.inspection.findings.size(), a.inspection.findings.size());
  EXPECT_EQ(b.inspection.submitted_tick, a.inspection.submitted_tick);
  ASSERT_EQ(b.inspection.units.size(), a.inspection.units.size());
  for (std::size_t i = 0; i < a.inspection.units.size(); ++i) {
    EXPECT_EQ(b.inspection.units[i].touched, a.inspection.units[i].touched)
        << a.inspection.units[i].Name();
    EXPECT_EQ(b.inspection.units[i].first_tick, a.inspection.units[i].first_tick)
        << a.inspection.units[i].Name();
  }
  EXPECT_EQ(Score(b, "caries").fp, Score(a, "caries").fp);
  EXPECT_EQ(b.inspection.views.size(), 1u);
  std::size_t seen = 0;
  for (const InspectionUnit& u : b.inspection.units) seen += u.seen;
  EXPECT_GT(seen, 0u) << "the view from the front shows the labial surfaces";
}

TEST(Inspectors, TheSkippingOneIsToldWhatItLeftOut) {
  const LessonResult& r = Take("skipping").result;
  const std::set<std::string> missed = NotExamined(r);
  for (const char* u : {"36 L", "37 L", "46 L", "47 L"})
    EXPECT_TRUE(missed.count(u)) << u << " was skipped and must be named as not examined";
  const auto partial = Messages(r, "coverage", RubricLine::Status::kPartial);
  // (The left cheek may still be brushed long enough later, from the left
  // teeth's buccal side; what counts is that the examination left it out in
  // its turn.)
  const auto sequence = Messages(r, "sequence", RubricLine::Status::kFail);
  bool named = false;
  for (const auto& m : sequence)
    named |= m.rfind("'buccal mucosa': left for a later step with", 0) == 0 &&
             m.find("cheek_left") != std::string::npos;
  EXPECT_TRUE(named) << ::testing::PrintToString(sequence);
  for (const char* tooth : {"36: ", "37: ", "46: ", "47: "}) {
    bool named = false;
    for (const auto& m : partial)
      named |= m.rfind(tooth, 0) == 0 && m.find("L") != std::string::npos;
    EXPECT_TRUE(named) << tooth << "L not named: " << ::testing::PrintToString(partial);
  }
  // The buccal mucosa step was left before it was done, with the left cheek missed.
  bool left = false;
  for (const StepResult& st : r.steps)
    left |= st.id == "buccal mucosa" && !st.completed &&
            std::count(st.missed.begin(), st.missed.end(), "cheek_left") == 1;
  EXPECT_TRUE(left);
  // The thorough one examined the left cheek.
  EXPECT_FALSE(NotExamined(Take("thorough").result).count("cheek_left"));
}

TEST(Inspectors, TheMistakenOneHasBothErrorsNamed) {
  const LessonResult& r = Take("mistaken").result;
  const LessonResult& t = Take("thorough").result;
  ScriptedInspector who("mistaken", LoadLessonSpec(Lesson()), *Take("mistaken").scene);
  ASSERT_EQ(who.false_findings().size(), 1u);
  ASSERT_EQ(who.missed_findings().size(), 1u);
  const Finding& wrong = who.false_findings()[0];
  const Finding& missed = who.missed_findings()[0];
  const std::string wrong_name =
      std::to_string(wrong.fdi) + " " + SurfaceCode(wrong.surface);
  const std::string missed_name =
      std::to_string(missed.fdi) + " " + SurfaceCode(missed.surface);
  const auto fails = Messages(r, "findings", RubricLine::Status::kFail);
  EXPECT_TRUE(AnyContains(fails, wrong_name + ": caries recorded on a sound surface"))
      << ::testing::PrintToString(fails);
  EXPECT_TRUE(AnyContains(fails, missed_name + ": caries missed"))
      << ::testing::PrintToString(fails);
  EXPECT_EQ(Score(r, "caries").fp, 1);
  if (!NotExamined(t).count(missed_name)) {
    EXPECT_EQ(Score(r, "caries").fn, Score(t, "caries").fn + 1);
  }
  EXPECT_LT(Score(r, "caries").specificity(), 1.0);
  EXPECT_LT(Score(r, "caries").sensitivity(), Score(t, "caries").sensitivity());
}

TEST(Inspectors, TheRoughOneIsScoredForDamageWithItsMoments) {
  const LessonResult& r = Take("rough").result;
  const auto damage = Messages(r, "damage", RubricLine::Status::kFail);
  bool tongue = false;
  for (const RubricLine& l : r.lines)
    if (l.category == "damage" && l.status == RubricLine::Status::kFail &&
        l.message.find("on tongue") != std::string::npos) {
      tongue = true;
      EXPECT_GT(l.tick, r.first_tick);
    }
  EXPECT_TRUE(tongue) << ::testing::PrintToString(damage);
  ASSERT_GT(r.inspection.presses.size(),
            Take("thorough").result.inspection.presses.size())
      << "the tip forced into a carious lesion";
  const LesionPress& p = *std::max_element(
      r.inspection.presses.begin(), r.inspection.presses.end(),
      [](const LesionPress& a, const LesionPress& b) { return a.force_n < b.force_n; });
  EXPECT_GT(p.force_n, 1.0);
  EXPECT_GT(p.force_n, r.rubric.lesion_force_n);
  EXPECT_TRUE(AnyContains(damage, p.where + ": ")) << ::testing::PrintToString(damage);
  EXPECT_TRUE(AnyContains(damage, "into the lesion")) << ::testing::PrintToString(damage);
  EXPECT_GT(
      Messages(r, "damage", RubricLine::Status::kFail).size(),
      Messages(Take("thorough").result, "damage", RubricLine::Status::kFail).size());
}

// A session started with the probe deep in the mouth's tissue, the hand then
// drawn out over 1,250 frames to a place where the whole probe is free (after
// 300 frames held). The engine brings the rendered tool to free space (never
// more than free_search_max_mm from the hand); once the hand is out in free
// space the tool rejoins it. No frame sends more than 0.5 N while the tool is
// more than 5 mm from a hand that is itself in free space (a pull toward a tool
// pinned on the far side of a wall), and the tool ends at the hand.
struct MouthStart {
  std::uint64_t inside_faults = 0;
  int free_frames = 0, pulling = 0;
  double worst_pull = 0, end_gap = 0;
};

// Whether the whole probe at X overlaps anything, and how deep it is in the
// objects whose names hold `name` (all when empty).
double Overlap(const CompiledScene& scene, const RigidTransform& X,
               const std::string& name, bool* any) {
  static CollisionScratch scratch;
  static std::vector<ContactPair> pairs(200000);
  const CollisionStats cs = FindContacts(scene.model->world, X, 0.0, &scratch,
                                         pairs.data(), static_cast<int>(pairs.size()));
  double deepest = 0;
  for (int k = 0; k < cs.pairs; ++k)
    if (ObjectName(scene.spec, pairs[k].object).find(name) != std::string::npos)
      deepest = std::max(deepest, -pairs[k].gap);
  if (any) *any = cs.pairs > 0 || cs.overflow;
  return deepest;
}

MouthStart RunMouthStart(const CompiledScene& scene, const RigidTransform& start,
                         const Vector3& out_W) {
  const EngineModel& model = *scene.model;
  EngineData d(model);
  ResetTool(start, &d);
  MouthStart r;
  for (int i = 0; i < 1950; ++i) {
    const double s = std::clamp((i - 300) / 1250.0, 0.0, 1.0);
    const RigidTransform X_WH(start.rotation(), start.translation() + s * out_W);
    Step(model, X_WH, &d);
    bool device_touches = false;
    Overlap(scene, X_WH, "", &device_touches);
    const double gap = (d.X_WG.translation() - X_WH.translation()).norm();
    if (!device_touches) {
      ++r.free_frames;
      if (gap > 5.0 && d.force_W.norm() > 0.5) ++r.pulling;
      if (gap > 5.0) r.worst_pull = std::max(r.worst_pull, d.force_W.norm());
    }
    r.end_gap = gap;
  }
  r.inside_faults = d.faults.inside;
  return r;
}

// The first of `moves` (offsets of the hand from `start`) where the whole
// probe is free; zero when none is.
Vector3 FirstFree(const CompiledScene& scene, const RigidTransform& start,
                  const std::vector<Vector3>& moves) {
  for (const Vector3& o : moves) {
    bool touches = true;
    Overlap(scene, RigidTransform(start.rotation(), start.translation() + o), "",
            &touches);
    if (!touches) return o;
  }
  return Vector3::Zero();
}

// Runs the start toward the first free place among `moves`; false (with a
// failure) when none is free.
bool RunToFreeSpace(const CompiledScene& scene, const RigidTransform& start,
                    const std::vector<Vector3>& moves, MouthStart* r, Vector3* out_W) {
  *out_W = FirstFree(scene, start, moves);
  if (out_W->isZero()) {
    ADD_FAILURE() << "no free place for the hand to go";
    return false;
  }
  *r = RunMouthStart(scene, start, *out_W);
  return true;
}

void ExpectRejoins(const MouthStart& r) {
  EXPECT_GE(r.inside_faults, 1u) << "the start was not deep: the case is not tested";
  EXPECT_GT(r.free_frames, 300) << "the hand never got out";
  EXPECT_EQ(r.pulling, 0) << "the hand, out in free space, was pulled back";
  EXPECT_LT(r.end_gap, 1e-6) << "the rendered tool ends at the hand";
}

int ToothIndex(const SceneSpec& spec, int fdi) {
  for (std::size_t i = 0; i < spec.objects.size(); ++i)
    if (spec.objects[i].kind == ObjectSpec::Kind::kTooth && spec.objects[i].fdi == fdi)
      return static_cast<int>(i);
  return -1;
}

// The probe's shank 2.5 mm or more inside the right cheek (leaning out over
// 46's buccal side, as the scripted insert once held it), drawn out lingually
// over the tooth and up.
TEST(DeepStartInTheMouth, AShankStartedInTheCheekRejoinsTheHandWithoutPullingItBack) {
  const SceneSpec spec =
      LoadSceneSpec((fs::path(SULCUS_SOURCE_DIR) / "scenes" / "oral_inspection.yaml"));
  const auto scene = CompileScene(spec, DefaultCacheDir());
  const int tooth = ToothIndex(spec, 46);
  ASSERT_GE(tooth, 0);
  ScriptTarget t = FindScriptTarget(*scene, "insert", tooth);
  t.shank_W = -t.shank_W;  // out over the buccal side, through the cheek
  const Quaternion q = ScriptOrientation(t);
  // The tip above the margin, moved out buccally until the shank is 2.5 mm in.
  RigidTransform start;
  double depth = 0, out_mm = 0;
  for (; out_mm <= 12; out_mm += 0.25) {
    start = RigidTransform(q, t.p_W + 3.0 * t.axis_W + out_mm * t.n_W);
    depth = Overlap(*scene, start, "cheek", nullptr);
    if (depth >= 2.5) break;
  }
  ASSERT_GE(depth, 2.5) << "the shank does not reach into the cheek";
  std::vector<Vector3> moves;
  for (double lingual = 4; lingual <= 16; lingual += 2)
    for (double up = 0; up <= 6; up += 2)
      moves.push_back(-(lingual + out_mm) * t.n_W + up * t.axis_W);
  MouthStart r;
  Vector3 out_W;
  if (!RunToFreeSpace(*scene, start, moves, &r, &out_W)) return;
  std::printf(
      "figure: the cheek: started %.2f mm in (the tip %.2f mm buccal of the "
      "margin); %llu deep-start faults, %d frames free, %d pulling back (worst "
      "%.2f N), ends %.3g mm from the hand\n",
      depth, out_mm, static_cast<unsigned long long>(r.inside_faults), r.free_frames,
      r.pulling, r.worst_pull, r.end_gap);
  ExpectRejoins(r);
}

// The closed mouth (the oral scene with mouth_open_mm: 0): the probe's tip
// 1 mm or more into 11's incisal edge, where the arches meet, its handle out
// in front; drawn out forward, through the upper lip, until it is free.
TEST(DeepStartInTheMouth, AClosedMouthStartRejoinsTheHandOutsideWithoutPullingItBack) {
  std::ifstream in(fs::path(SULCUS_SOURCE_DIR) / "scenes" / "oral_inspection.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  const std::size_t at = yaml.find("\nmouth_open_mm:");
  ASSERT_NE(at, std::string::npos);
  yaml.replace(at, yaml.find('\n', at + 1) - at, "\nmouth_open_mm: 0");
  const fs::path file = Out("closed_mouth.yaml");
  std::ofstream(file) << yaml;
  const SceneSpec spec = LoadSceneSpec(file);
  ASSERT_EQ(spec.mouth_open_mm, 0);
  const auto scene = CompileScene(spec, DefaultCacheDir());
  const int tooth = ToothIndex(spec, 11);
  ASSERT_GE(tooth, 0);
  ScriptTarget t = FindScriptTarget(*scene, "poke", tooth);
  const Vector3 forward = spec.objects[static_cast<std::size_t>(tooth)].X_WO.rotation() *
                          Vector3::UnitY();  // labial
  t.tool_axis_W = forward;                   // the handle out in front of the mouth
  const Quaternion q = ScriptOrientation(t);
  RigidTransform start;
  double depth = 0;
  for (double into = 0; into <= 4; into += 0.25) {
    start = RigidTransform(q, t.p_W - into * t.n_W);
    depth = Overlap(*scene, start, "tooth", nullptr);
    if (depth >= 1.0) break;
  }
  ASSERT_GE(depth, 1.0) << "the tip does not reach into the teeth";
  std::vector<Vector3> moves;
  for (double ahead = 15; ahead <= 40; ahead += 5) moves.push_back(ahead * forward);
  MouthStart r;
  Vector3 out_W;
  if (!RunToFreeSpace(*scene, start, moves, &r, &out_W)) return;
  std::printf(
      "figure: the closed mouth: started %.2f mm in the teeth; %llu deep-start "
      "faults, %d frames free, %d pulling back (worst %.2f N), ends %.3g mm "
      "from the hand, %.0f mm ahead\n",
      depth, static_cast<unsigned long long>(r.inside_faults), r.free_frames, r.pulling,
      r.worst_pull, r.end_gap, out_W.norm());
  ExpectRejoins(r);
}

}  // namespace
}  // namespace sulcus
