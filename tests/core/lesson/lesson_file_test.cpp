// Lesson files: the shipped lesson reads; every error at once with its place;
// what cannot be scored or drawn is refused when the file is read.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "core/lesson/answers.h"
#include "core/lesson/lesson_spec.h"
#include "tests/common/load_errors.h"
#include "tests/common/output.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

fs::path Out(const std::string& name) { return test::OutputPath("lesson", name); }

fs::path Write(const std::string& name, const std::string& text) {
  return test::WriteText(Out(name), text);
}

fs::path Lesson() {
  return fs::path(SULCUS_SOURCE_DIR) / "lessons" / "periodontal_probing.yaml";
}

fs::path ProbingScene() {
  return fs::path(SULCUS_SOURCE_DIR) / "scenes" / "periodontal_probing.yaml";
}

std::vector<std::string> Errors(const fs::path& file) {
  return test::ErrorLines([&] { LoadLessonSpec(file); });
}

TEST(LessonFile, TheShippedLessonIsValid) {
  const LessonSpec s = LoadLessonSpec(Lesson());
  EXPECT_EQ(s.teeth, (std::vector<int>{47, 46, 45, 44}));
  ASSERT_EQ(s.path.size(), 24u);
  EXPECT_EQ(s.path.front().ToString(), "47 DB") << "the buccal pass starts distal of 47";
  EXPECT_EQ(s.path[5].ToString(), "46 MB");
  EXPECT_EQ(s.path[12].ToString(), "44 ML") << "the lingual pass comes back from 44";
  EXPECT_EQ(s.steps.size(), 4u);
  EXPECT_TRUE(s.practice());
  EXPECT_EQ(s.probe, "unc15");
}

TEST(LessonFile, EveryErrorAtOnceWithItsPlace) {
  const fs::path scene = ProbingScene();
  const fs::path p = Write("bad.yaml",
                           "name: bad\n"
                           "scene: " +
                               scene.string() +
                               "\n"
                               "mode: practise\n"
                               "teeth: [46, 36]\n"
                               "path: [\"46 DB\", \"46 XX\", \"46 DB\"]\n"
                               "stepz: []\n"
                               "rubric:\n"
                               "  force_band_n: [0.3, 0.2]\n"
                               "  weights: {technik: 3}\n");
  const auto e = Errors(p);
  const std::string f = p.string();
  EXPECT_EQ(
      e,
      (std::vector<std::string>{
          f + ":6:1: unknown key 'stepz' in the lesson; did you mean 'steps'?",
          f + ":3:7: unknown mode 'practise'; did you mean 'practice'?",
          f + ":9:13: unknown key 'technik' in 'weights' (expected one of: technique, "
              "reading, charting, force, angulation, "
              "coverage, bleeding, completeness, diagnosis, findings, sequence, damage)",
          f + ":8:17: 'force_band_n' must be [low, high] with low < high",
          f + ":4:13: tooth 36 is not in the scene periodontal_probing.yaml",
          f + ":5:17: a path entry is a tooth and a site, such as \"46 DB\" (sites MB, "
              "B, DB, ML, L, DL)",
          f + ":5:26: site 46 DB is twice in the path",
          f + ":1:1: a lesson needs 'steps:', a list of what the student does in "
              "order"}));
  EXPECT_EQ(
      Errors(Write("noscene.yaml", "steps: [{instruction: x, complete: read}]\n")),
      (std::vector<std::string>{
          Out("noscene.yaml").string() +
          ":1:1: a lesson needs 'scene:', the scene file it runs on (relative to the "
          "lesson's folder)"}));
  const auto missing = Errors(Out("missing.yaml"));
  ASSERT_EQ(missing.size(), 1u);
  EXPECT_NE(missing[0].find("no such lesson file"), std::string::npos);
}

// a pass angle below the full-credit one.
TEST(LessonFile, ARubricThatCannotScoreIsRefused) {
  const fs::path scene = ProbingScene();
  const fs::path p = Write("zero_rubric.yaml",
                           "name: zero\nscene: " + scene.string() +
                               "\nsteps: [{instruction: x, complete: read}]\n"
                               "rubric:\n"
                               "  angle_full_deg: 90\n"
                               "  angle_pass_deg: 10\n"
                               "  weights: {technique: 0, reading: 0, charting: 0, "
                               "force: 0, angulation: 0, coverage: 0, bleeding: 0, "
                               "completeness: 0, diagnosis: 0, findings: 0, sequence: 0, "
                               "damage: 0}\n");
  const auto e = Errors(p);
  const std::string f = p.string();
  EXPECT_NE(std::find(e.begin(), e.end(),
                      f + ":7:12: every weight in 'weights' is 0, so every attempt "
                          "would score 0; give the lines that count a weight above 0"),
            e.end())
      << ::testing::PrintToString(e);
  EXPECT_NE(std::find(e.begin(), e.end(),
                      f + ":5:3: 'angle_pass_deg' (10) must be at least 'angle_full_deg' "
                          "(90): full credit is for a smaller tilt than a pass"),
            e.end())
      << ::testing::PrintToString(e);
}

// A case no chart of the lesson's teeth can be is refused: stage I localized
// on 4 teeth would put 2 of 4 (50 %) in its band.
TEST(LessonFile, ACaseTheTeethCannotHoldIsRefused) {
  const fs::path scene = ProbingScene();
  const fs::path p =
      Write("impossible_case.yaml", "name: impossible\nscene: " + scene.string() +
                                        "\nteeth: [47, 46, 45, 44]\n"
                                        "case: {stage: I, extent: localized}\n"
                                        "steps: [{instruction: x, complete: read}]\n");
  const auto e = Errors(p);
  EXPECT_NE(std::find(e.begin(), e.end(),
                      p.string() + ":4:7: a case of stage I, localized needs at least 7 "
                                   "teeth (2 in its band must be under 30 %); the lesson "
                                   "has 4"),
            e.end())
      << ::testing::PrintToString(e);
  const fs::path ok =
      Write("possible_case.yaml", "name: possible\nscene: " + scene.string() +
                                      "\nteeth: [47, 46, 45, 44]\n"
                                      "case: {stage: II, extent: localized}\n"
                                      "steps: [{instruction: x, complete: read}]\n");
  EXPECT_TRUE(Errors(ok).empty()) << ::testing::PrintToString(Errors(ok));
  const fs::path pattern =
      Write("pattern_case.yaml", "name: pattern\nscene: " + scene.string() +
                                     "\nteeth: [47, 46, 45, 44]\n"
                                     "case: {stage: III, extent: molar-incisor}\n"
                                     "steps: [{instruction: x, complete: read}]\n");
  const auto pe = Errors(pattern);
  ASSERT_EQ(pe.size(), 1u) << ::testing::PrintToString(pe);
  // The sextant has no incisor: the pattern cannot be drawn on it.
  EXPECT_NE(pe[0].find(":4:7: a molar-incisor case needs first molars and incisors among "
                       "the lesson's teeth (47, 46, 45, 44)"),
            std::string::npos)
      << pe[0];
}

// A key given twice is an error naming both lines (a YAML reader would keep
// one silently): in a lesson, in answers, and a tooth twice in a chart.
// A calibration lesson names its reference examiner's chart: a file that is
// not there, a chart with a tooth the lesson does not examine, a case drawn
// anew each attempt, and no reference at all are refused at their lines.
TEST(LessonFile, ACalibrationReferenceThatCannotBeUsedIsRefused) {
  const std::string head = "name: calibration\nscene: " + ProbingScene().string() +
                           "\nteeth: [47, 46, 45, 44]\nsteps:\n  - instruction: probe\n"
                           "    complete: read\n";
  Write("ref_other_tooth.yaml", "chart:\n  36: {pd: [3, 2, 3, 3, 2, 3]}\n");
  const fs::path a =
      Write("cal_a.yaml", head + "calibration: {reference: nowhere.yaml}\n");
  const fs::path b =
      Write("cal_b.yaml", head + "calibration: {reference: ref_other_tooth.yaml}\n");
  const fs::path c = Write("cal_c.yaml", head + "calibration: {}\n");
  const fs::path d =
      Write("cal_d.yaml", head +
                              "case: {stage: III, extent: localized, seed: "
                              "random}\ncalibration: {reference: x.yaml}\n");
  const auto has = [](const std::vector<std::string>& e, const std::string& what) {
    return std::any_of(e.begin(), e.end(), [&](const std::string& l) {
      return l.find(what) != std::string::npos;
    });
  };
  auto e = Errors(a);
  EXPECT_TRUE(has(e, a.string() + ":7:")) << ::testing::PrintToString(e);
  EXPECT_TRUE(has(e, "no reference examiner's chart at")) << ::testing::PrintToString(e);
  EXPECT_TRUE(has(e, "nowhere.yaml")) << ::testing::PrintToString(e);
  e = Errors(b);
  EXPECT_TRUE(has(e, "ref_other_tooth.yaml:2:")) << ::testing::PrintToString(e);
  EXPECT_TRUE(has(e, "36")) << ::testing::PrintToString(e);
  e = Errors(c);
  EXPECT_TRUE(has(e, c.string() + ":7:")) << ::testing::PrintToString(e);
  EXPECT_TRUE(has(e, "'calibration' needs 'reference'")) << ::testing::PrintToString(e);
  e = Errors(d);
  EXPECT_TRUE(has(e, "draws a new one for each attempt")) << ::testing::PrintToString(e);

  const LessonSpec shipped = LoadLessonSpec(fs::path(SULCUS_SOURCE_DIR) / "lessons" /
                                            "periodontal_calibration.yaml");
  ASSERT_TRUE(shipped.has_reference());
  ASSERT_NE(shipped.reference.Find(46), nullptr);
  EXPECT_EQ(shipped.reference.Find(46)->sites[2].pd_mm, 6)
      << "46 DB as the examiner read it";
}

TEST(LessonFile, AKeyGivenTwiceIsRefusedWithBothLines) {
  const fs::path scene = ProbingScene();
  const fs::path lesson = Write("twice.yaml",
                                "name: twice\n"
                                "scene: " +
                                    scene.string() +
                                    "\n"
                                    "teeth: [46]\n"
                                    "teeth: [47]\n");
  const auto e = Errors(lesson);
  ASSERT_FALSE(e.empty());
  EXPECT_NE(std::find(e.begin(), e.end(),
                      lesson.string() +
                          ":4:1: 'teeth' is given twice in the lesson (first at line "
                          "3); give it once"),
            e.end())
      << ::testing::PrintToString(e);
  const fs::path answers = Write("twice_answers.yaml",
                                 "chart:\n"
                                 "  46: {pd: [5, 4, 7, 5, 4, 6]}\n"
                                 "  46: {pd: [5, 4, 7, 5, 4, 6]}\n"
                                 "diagnosis: {stage: III, extent: localized}\n"
                                 "diagnosis: {periodontitis: false}\n");
  const auto a = test::ErrorLines([&] { LoadAnswers(answers); });
  const std::string f = answers.string();
  EXPECT_NE(std::find(a.begin(), a.end(),
                      f + ":3:3: '46' is given twice in 'chart' (a tooth) (first at line "
                          "2); give it once"),
            a.end())
      << ::testing::PrintToString(a);
  EXPECT_NE(std::find(a.begin(), a.end(),
                      f + ":5:1: 'diagnosis' is given twice in the answers (first at "
                          "line 4); give it once"),
            a.end())
      << ::testing::PrintToString(a);
}

// An error says what the file was read as: a lesson's, an answers file's.
TEST(LessonFile, ItsErrorsNameTheKindOfFile) {
  const fs::path missing = Out("no_such_lesson.yaml");
  try {
    LoadLessonSpec(missing);
    ADD_FAILURE() << "a missing lesson loaded";
  } catch (const LoadError& e) {
    EXPECT_EQ(e.kind(), "lesson file");
    EXPECT_EQ(e.Summary(), "lesson file " + missing.string() + ": 1 error");
  }
  try {
    LoadAnswers(Write("bad_kind.yaml", "chart: 3\nentries: 4\n"));
    ADD_FAILURE() << "bad answers loaded";
  } catch (const LoadError& e) {
    EXPECT_EQ(e.kind(), "answers file");
    EXPECT_EQ(e.Summary(),
              "answers file " + Out("bad_kind.yaml").string() + ": 2 errors");
  }
}

}  // namespace
}  // namespace sulcus
