// A generated case saved as a scene of its own: the lesson's scene with its
// teeth's pockets, recession and bleeding replaced, read back to the same true
// chart and classification, usable by a lesson without `case:`.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "core/anatomy/tooth.h"
#include "core/lesson/lesson_spec.h"
#include "tests/common/load_errors.h"
#include "tests/common/meshes.h"
#include "tests/common/output.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

fs::path Dir(const std::string& name) { return test::FreshOutputPath("case", name); }

TEST(CaseScene, ASavedCaseReadsBackAsTheDrawnChartAndALessonCanUseIt) {
  const LessonSpec lesson = LoadLessonSpec(fs::path(SULCUS_SOURCE_DIR) / "lessons" /
                                           "periodontal_probing.yaml");
  ASSERT_FALSE(lesson.case_spec.generated);
  CaseSpec c;
  c.generated = true;
  c.stage = Stage::kII;
  c.extent = Extent::kGeneralized;
  const fs::path dir = Dir("saved");
  const fs::path out = dir / "sextant_stage_ii.yaml";
  const SceneSpec back = SaveCaseScene(lesson, c, 11, out);

  const SceneSpec drawn = ApplyCase(LoadSceneSpec(lesson.scene), lesson.teeth, c, 11);
  const Diagnosis d = Classify2017(TrueChart(back, lesson.teeth));
  EXPECT_EQ(d.kind, Diagnosis::Kind::kPeriodontitis);
  EXPECT_EQ(d.stage, Stage::kII);
  EXPECT_EQ(d.extent, Extent::kGeneralized);
  for (const ObjectSpec& o : back.objects)
    for (const ObjectSpec& t : drawn.objects)
      if (o.kind == ObjectSpec::Kind::kTooth && t.kind == o.kind && o.fdi == t.fdi) {
        EXPECT_EQ(o.pocket_mm, t.pocket_mm) << o.fdi;
        EXPECT_EQ(o.recession_mm, t.recession_mm) << o.fdi;
        EXPECT_EQ(o.bleeding, t.bleeding) << o.fdi;
      }
  // Everything else is the lesson's scene.
  const SceneSpec base = LoadSceneSpec(lesson.scene);
  EXPECT_EQ(back.objects.size(), base.objects.size());
  EXPECT_EQ(back.effects, base.effects);
  EXPECT_EQ(back.probe, base.probe);
  EXPECT_EQ(back.haptics.max_force_n, base.haptics.max_force_n);
  EXPECT_NE(back.name.find("stage II, generalized, seed 11"), std::string::npos)
      << back.name;
  std::ifstream f(out);
  std::string first;
  std::getline(f, first);
  EXPECT_EQ(first.rfind("# ", 0), 0u) << "the case is named in the file's first lines";

  // A lesson on the saved scene, without `case:`, loads and charts the same truth.
  std::ofstream(dir / "lesson.yaml")
      << "name: fixed case\nscene: sextant_stage_ii.yaml\n"
         "steps:\n  - {id: read, instruction: Probe every site., complete: read}\n";
  const LessonSpec fixed = LoadLessonSpec(dir / "lesson.yaml");
  EXPECT_EQ(std::set<int>(fixed.teeth.begin(), fixed.teeth.end()),
            std::set<int>(lesson.teeth.begin(), lesson.teeth.end()));
  const PerioChart a = TrueChart(LoadSceneSpec(fixed.scene), lesson.teeth),
                   b = TrueChart(drawn, lesson.teeth);
  ASSERT_EQ(a.teeth.size(), b.teeth.size());
  for (std::size_t t = 0; t < a.teeth.size(); ++t)
    for (int s = 0; s < kSitesPerTooth; ++s)
      EXPECT_EQ(a.teeth[t].sites[s].pd_mm, b.teeth[t].sites[s].pd_mm);
}

TEST(CaseScene, ASceneWithMeshFilesIsSavedOnlyBesideItself) {
  const fs::path src = Dir("with_mesh");
  const fs::path elsewhere = Dir("elsewhere");
  // The shipped probing scene plus a mesh object, in a folder of its own.
  std::ifstream in(fs::path(SULCUS_SOURCE_DIR) / "scenes" / "periodontal_probing.yaml");
  std::stringstream text;
  text << in.rdbuf();
  test::WriteTetrahedronStl(src / "block.stl", 4);
  std::ofstream(src / "scene.yaml")
      << text.str() << "  - mesh: block.stl\n    tissue: bone\n    at: [0, 0, -40]\n";
  std::ofstream(src / "lesson.yaml") << "name: x\nscene: scene.yaml\nsteps:\n  - {id: r, "
                                        "instruction: x, complete: read}\n";
  const LessonSpec lesson = LoadLessonSpec(src / "lesson.yaml");
  CaseSpec c;
  c.generated = true;
  try {
    SaveCaseScene(lesson, c, 3, elsewhere / "case.yaml");
    FAIL() << "saved a scene with relative mesh paths into another folder";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("names mesh files relative to its folder"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(elsewhere / "case.yaml"));
  const SceneSpec beside = SaveCaseScene(lesson, c, 3, src / "case.yaml");
  EXPECT_EQ(beside.objects.size(), LoadSceneSpec(src / "scene.yaml").objects.size())
      << "the block is kept";
  EXPECT_TRUE(fs::exists(src / "case.yaml"));
}

// Furcation in the scene is the chart's truth, and class II raises stage II to III.
TEST(CaseScene, AFurcationInTheSceneIsInTheTrueChartAndRaisesTheStage) {
  const LessonSpec lesson = LoadLessonSpec(fs::path(SULCUS_SOURCE_DIR) / "lessons" /
                                           "periodontal_probing.yaml");
  SceneSpec scene = LoadSceneSpec(lesson.scene);
  // A stage II chart: 3-4 mm of interdental CAL at several teeth, no PD >= 6.
  for (ObjectSpec& o : scene.objects) {
    if (o.kind != ObjectSpec::Kind::kTooth) continue;
    o.pocket_mm = {4, 3, 4, 4, 3, 4};
    o.recession_mm = {1.5, 1.5, 1.5, 1.5, 1.5, 1.5};
    o.bleeding = {};
  }
  const Diagnosis before = Classify2017(TrueChart(scene, lesson.teeth));
  ASSERT_EQ(before.stage, Stage::kII);
  for (ObjectSpec& o : scene.objects)
    if (o.kind == ObjectSpec::Kind::kTooth && o.fdi == 46) o.furcation["B"] = 2;
  const PerioChart truth = TrueChart(scene, lesson.teeth);
  ASSERT_NE(truth.Find(46), nullptr);
  EXPECT_EQ(truth.Find(46)->furcation, 2);
  EXPECT_EQ(Classify2017(truth).stage, Stage::kIII);
}

// A scene's patient: the history read from `patient:`, the mobility from a
// tooth, and the radiograph's bone loss measured on the anatomy (the crest
// under the deepest attachment loss over the root's length); the grade follows.
TEST(CaseScene, APatientInTheSceneGivesStageIVAndTheGrade) {
  const fs::path dir = Dir("patient");
  std::ifstream in(fs::path(SULCUS_SOURCE_DIR) / "scenes" / "periodontal_probing.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string scene_text = text.str();
  const std::string teeth = "objects:\n";
  ASSERT_NE(scene_text.find(teeth), std::string::npos);
  scene_text.replace(
      scene_text.find(teeth), teeth.size(),
      "patient: {age: 38, cigarettes_per_day: 12, teeth_lost_to_periodontitis: "
      "0, opposing_pairs: 12}\n" +
          teeth);
  const std::string tooth46 = "  - tooth: 46\n";
  ASSERT_NE(scene_text.find(tooth46), std::string::npos);
  scene_text.replace(scene_text.find(tooth46), tooth46.size(),
                     tooth46 + "    mobility: 2\n");
  std::ofstream(dir / "scene.yaml") << scene_text;
  const SceneSpec scene = LoadSceneSpec(dir / "scene.yaml");
  ASSERT_TRUE(scene.patient.given);
  EXPECT_EQ(scene.patient.age_years, 38);
  EXPECT_EQ(scene.patient.cigarettes_per_day, 12);
  const PerioChart truth = TrueChart(scene, {47, 46, 45, 44});
  EXPECT_EQ(truth.Find(46)->mobility, 2);
  // 46's worst site: a 7 mm pocket with 1 mm of recession: the crest 7.5 mm
  // below the CEJ, 6 mm below a healthy crest, over the root below it.
  const double root = Dimensions(FdiTooth::Parse(46)).root_length;
  ASSERT_TRUE(truth.patient.bone_loss_pct.has_value());
  EXPECT_NEAR(*truth.patient.bone_loss_pct, 100.0 * 6.0 / (root - 1.5), 1e-9);
  const Diagnosis d = Classify2017(truth);
  EXPECT_EQ(d.stage, Stage::kIV) << "stage III with mobility 2: " << d.Summary();
  EXPECT_EQ(d.grade, Grade::kC) << "12 cigarettes a day";
  EXPECT_GT(d.bone_loss_per_age, 1.0) << "about 46 % lost at 38";

  // A wrong key, a wrong value: the file's line and what is expected.
  std::ofstream(dir / "bad.yaml") << "patient: {age: 300, smoker: true}\n"
                                     "objects:\n  - tooth: 46\n    mobility: 4\n";
  try {
    LoadSceneSpec(dir / "bad.yaml");
    ADD_FAILURE() << "a bad patient loaded";
  } catch (const LoadError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("bad.yaml:1:"), std::string::npos) << what;
    EXPECT_NE(what.find("'smoker'"), std::string::npos) << what;
    EXPECT_NE(what.find("age"), std::string::npos) << what;
    EXPECT_NE(what.find("bad.yaml:4:"), std::string::npos) << what;
    EXPECT_NE(what.find("mobility"), std::string::npos) << what;
  }
}

// `missing:` lists the teeth that are gone: the chart holds them as missing,
// the ones lost to periodontitis are the patient's count (tooth loss makes a
// stage II chart stage III), and the others keep their places in the arch.
TEST(CaseScene, MissingTeethAreChartedMissingAndTheLostOnesCount) {
  const fs::path dir = Dir("missing");
  std::ofstream(dir / "scene.yaml")
      << "arch: true\ngingiva: true\npatient: {age: 50}\n"
         "missing: {36: periodontitis, 25: caries, 18: unknown}\n"
         "objects:\n"
         "  - tooth: 35\n    pockets_mm: [4, 2, 4, 3, 2, 3]\n"
         "  - tooth: 37\n    pockets_mm: [5, 3, 5, 4, 3, 4]\n"
         "  - tooth: 24\n    pockets_mm: [4, 2, 5, 3, 2, 4]\n";
  const SceneSpec scene = LoadSceneSpec(dir / "scene.yaml");
  ASSERT_EQ(scene.missing.size(), 3u);
  EXPECT_EQ(scene.missing.at(36).reason, "periodontitis");
  EXPECT_EQ(scene.missing.at(25).line, 4);
  EXPECT_EQ(scene.patient.teeth_lost_to_periodontitis, 1);
  int teeth = 0;
  for (const ObjectSpec& o : scene.objects) {
    teeth += o.kind == ObjectSpec::Kind::kTooth;
    EXPECT_NE(o.fdi, 36) << o.name;
  }
  EXPECT_EQ(teeth, 3);
  const PerioChart truth = TrueChart(scene, {35, 37, 24});
  for (int fdi : {36, 25, 18}) {
    ASSERT_NE(truth.Find(fdi), nullptr) << fdi;
    EXPECT_FALSE(truth.Find(fdi)->present) << fdi;
  }
  EXPECT_TRUE(truth.Find(35)->present);
  // Worst interdental CAL 3 mm (5 - 1.5, half down): stage II by CAL, and
  // one tooth lost to periodontitis makes it stage III; the extent counts the
  // teeth present only.
  const Diagnosis d = Classify2017(truth);
  EXPECT_EQ(d.stage, Stage::kIII) << d.Summary();
  bool said = false;
  for (const std::string& l : d.path) said |= l.find("1 teeth lost") != std::string::npos;
  EXPECT_TRUE(said) << "the path names the tooth loss";

  // A lesson that asks for a missing tooth is told it is missing.
  std::ofstream(dir / "lesson.yaml")
      << "scene: scene.yaml\nteeth: [35, 36]\nsteps:\n  - instruction: probe\n"
         "    complete: read\n";
  const std::vector<std::string> lesson_errors =
      test::ErrorLines([&] { LoadLessonSpec(dir / "lesson.yaml"); });
  EXPECT_TRUE(std::any_of(lesson_errors.begin(), lesson_errors.end(),
                          [](const std::string& l) {
                            return l.find(
                                       "lesson.yaml:2:13: tooth 36 is not in the scene "
                                       "scene.yaml (it is missing there: "
                                       "periodontitis)") != std::string::npos;
                          }))
      << ::testing::PrintToString(lesson_errors);

  // A tooth both missing and an object, a reason that is none, a number that
  // is not a tooth, and a count of lost teeth below the list's: each with its line.
  std::ofstream(dir / "bad.yaml")
      << "patient: {age: 50, teeth_lost_to_periodontitis: 1}\n"
         "missing: {36: periodontitis, 46: periodontitis, 26: forgot, 19: unknown}\n"
         "objects:\n  - tooth: 36\n";
  try {
    LoadSceneSpec(dir / "bad.yaml");
    ADD_FAILURE() << "a bad missing list loaded";
  } catch (const LoadError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("tooth 36 is listed as missing and is an object of the scene "
                        "(line 4)"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("'forgot' is not a reason"), std::string::npos) << what;
    EXPECT_NE(what.find("'19' is not a tooth"), std::string::npos) << what;
    EXPECT_NE(what.find("bad.yaml:1:"), std::string::npos) << what;
    EXPECT_NE(what.find("lists 2 teeth lost to periodontitis"), std::string::npos)
        << what;
  }
}

// Every stage, extent and grade asked of ApplyCase, each over `seeds` seeds:
// each case drawn goes to `check` (with its name and seed); returns the
// combinations no seed could draw, and checks that a seed alone never decides.
template <typename Check>
std::set<std::string> DrawEveryCase(const SceneSpec& scene, const std::vector<int>& teeth,
                                    const std::vector<Extent>& extents, int seeds,
                                    int* drawn, Check check) {
  std::set<std::string> refused;
  for (const Stage stage : {Stage::kI, Stage::kII, Stage::kIII, Stage::kIV})
    for (const Extent extent : extents)
      for (const Grade grade : {Grade::kNone, Grade::kA, Grade::kB, Grade::kC}) {
        CaseSpec c;
        c.generated = true;
        c.stage = stage;
        c.extent = extent;
        c.grade = grade;
        const std::string name =
            std::string(ToString(stage)) + " " + ToString(extent) + " " + ToString(grade);
        int ok = 0, failed = 0;
        for (std::uint64_t seed = 1; seed <= static_cast<std::uint64_t>(seeds); ++seed) {
          try {
            const SceneSpec s = ApplyCase(scene, teeth, c, seed);
            check(s, c, name + " seed " + std::to_string(seed));
            ++ok;
          } catch (const std::runtime_error&) {
            ++failed;
          }
        }
        EXPECT_TRUE(ok == 0 || failed == 0) << name << ": drawn " << ok << ", refused "
                                            << failed << " (a seed should not decide)";
        if (ok == 0) refused.insert(name);
        *drawn += ok;
      }
  return refused;
}

// Generated cases of every stage, extent and grade the sextant's teeth can give
// classify as asked over many seeds; the others are refused every time.
TEST(CaseScene, EveryStageExtentAndGradeIsDrawnAsAskedOrRefused) {
  const LessonSpec lesson = LoadLessonSpec(fs::path(SULCUS_SOURCE_DIR) / "lessons" /
                                           "periodontal_probing.yaml");
  const SceneSpec scene = LoadSceneSpec(lesson.scene);
  int drawn = 0;
  const std::set<std::string> refused = DrawEveryCase(
      scene, lesson.teeth, {Extent::kLocalized, Extent::kGeneralized}, 8, &drawn,
      [&](const SceneSpec& s, const CaseSpec& c, const std::string& name) {
        const Diagnosis d = Classify2017(TrueChart(s, lesson.teeth));
        EXPECT_EQ(d.stage, c.stage) << name;
        EXPECT_EQ(d.extent, c.extent) << name;
        if (c.grade != Grade::kNone) {
          EXPECT_EQ(d.grade, c.grade) << name;
        }
        EXPECT_EQ(s.patient.given, c.grade != Grade::kNone || c.stage == Stage::kIV)
            << name;
      });
  // Four teeth cannot hold a localized stage I (its 2 teeth are 50 %), and
  // bone loss at stage II or more is more than a quarter of a percent a year at
  // any age: grade A needs stage I.
  EXPECT_EQ(refused,
            (std::set<std::string>{"I localized none", "I localized A", "I localized B",
                                   "I localized C", "II localized A", "II generalized A",
                                   "III localized A", "III generalized A",
                                   "IV localized A", "IV generalized A"}))
      << ::testing::PrintToString(refused);
  std::printf("figure: %d cases drawn as asked over %zu combinations refused\n", drawn,
              refused.size());
}

// The whole mouth (the full examination's 26 teeth): every stage, extent
// (the molar-incisor pattern too) and grade over many seeds, each drawn with
// the history of its teeth (why the scene's two gaps were lost, teeth taken out
// for stage IV by tooth loss), furcation of diseased molars and mobility, and
// classified as asked. Grade A is drawn at stage I and at a localized stage II
// (the least loss on a few teeth, a patient of 60 to 90); with more teeth or a
// deeper stage the worst tooth's bone loss over age is a quarter of a percent a
// year or more even at 90, and it is refused.
TEST(CaseScene, WholeMouthCasesOfEveryStageExtentAndGradeAreDrawnAsAsked) {
  const LessonSpec lesson = LoadLessonSpec(fs::path(SULCUS_SOURCE_DIR) / "lessons" /
                                           "periodontal_examination.yaml");
  ASSERT_EQ(lesson.teeth.size(), 26u);
  const SceneSpec scene = LoadSceneSpec(lesson.scene);
  int drawn = 0, taken_out = 0, furcation = 0, molar_incisor = 0;
  const std::set<std::string> refused = DrawEveryCase(
      scene, lesson.teeth,
      {Extent::kLocalized, Extent::kGeneralized, Extent::kMolarIncisor}, 6, &drawn,
      [&](const SceneSpec& s, const CaseSpec& c, const std::string& name) {
        const PerioChart truth = TrueChart(s, lesson.teeth);
        const Diagnosis d = Classify2017(truth);
        EXPECT_EQ(d.kind, Diagnosis::Kind::kPeriodontitis) << name;
        EXPECT_EQ(d.stage, c.stage) << name;
        EXPECT_EQ(d.extent, c.extent) << name;
        if (c.grade != Grade::kNone) {
          EXPECT_EQ(d.grade, c.grade) << name;
        }
        // The gaps and the teeth taken out are charted missing, each counted
        // once in the teeth lost to periodontitis.
        int lost = 0;
        for (const auto& [fdi, m] : s.missing) {
          lost += m.reason == "periodontitis";
          ASSERT_NE(truth.Find(fdi), nullptr) << name;
          EXPECT_FALSE(truth.Find(fdi)->present) << name;
        }
        EXPECT_GE(s.missing.size(), 2u) << "the scene's own gaps";
        EXPECT_EQ(truth.patient.teeth_lost_to_periodontitis, lost) << name;
        if (c.stage < Stage::kIII) {
          EXPECT_EQ(lost, 0) << name;
        }
        taken_out += s.missing.size() > 2;
        LessonSpec fitted = lesson;
        FitLessonToCase(&fitted, s);
        EXPECT_EQ(fitted.teeth.size(), 28 - s.missing.size()) << name;
        EXPECT_EQ(fitted.path.size(), 6 * fitted.teeth.size()) << name;
        for (const ToothChart& t : truth.teeth) furcation += t.present && t.furcation > 0;
        molar_incisor += d.extent == Extent::kMolarIncisor;
      });
  EXPECT_EQ(refused, (std::set<std::string>{"II generalized A", "II molar-incisor A",
                                            "III localized A", "III generalized A",
                                            "III molar-incisor A", "IV localized A",
                                            "IV generalized A", "IV molar-incisor A"}))
      << ::testing::PrintToString(refused);
  EXPECT_GT(taken_out, 0) << "stage IV by tooth loss takes teeth out";
  EXPECT_GT(furcation, 0);
  EXPECT_GT(molar_incisor, 0);
  std::printf(
      "figure: whole mouth, %d cases drawn as asked (%d with teeth taken out, %d "
      "furcations, %d molar-incisor), %zu combinations refused\n",
      drawn, taken_out, furcation, molar_incisor, refused.size());
}

}  // namespace
}  // namespace sulcus
