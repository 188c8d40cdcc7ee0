// Answers files: the chart and entries forms read alike, and what a student
// could not have entered is refused with file:line:column.
#include "core/lesson/answers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/common/load_errors.h"
#include "tests/common/output.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

fs::path Out(const std::string& name) { return test::OutputPath("lesson", name); }

fs::path Write(const std::string& name, const std::string& text) {
  return test::WriteText(Out(name), text);
}

std::vector<std::string> Errors(const fs::path& file) {
  return test::ErrorLines([&] { LoadAnswers(file); });
}

// An answers file names real teeth and is a chart, not a flood.
TEST(Answers, TeethAreFdiNumbersAndEntriesAreBounded) {
  const auto bad = Errors(Write("bad_teeth.yaml",
                                "chart:\n"
                                "  19: {pd: [3, 3, 3, 3, 3, 3]}\n"
                                "entries:\n"
                                "  - {site: \"50 DB\", pd: 3}\n"));
  ASSERT_EQ(bad.size(), 2u) << ::testing::PrintToString(bad);
  EXPECT_NE(bad[0].find(":2:3: FDI 19 does not exist"), std::string::npos) << bad[0];
  EXPECT_NE(bad[1].find(":4:12: FDI 50 does not exist"), std::string::npos) << bad[1];
  std::string many = "entries:\n";
  for (int i = 0; i < 10001; ++i) many += "  - {site: \"46 DB\", pd: 3}\n";
  const auto flood = Errors(Write("flood.yaml", many));
  ASSERT_EQ(flood.size(), 1u);
  EXPECT_NE(flood[0].find("'entries' holds 10001 entries; an answers file holds at most "
                          "10000"),
            std::string::npos)
      << flood[0];
}

TEST(Answers, ChartAndEntriesFormsAndTheirErrors) {
  const fs::path p = Write("answers.yaml",
                           "chart:\n"
                           "  46: {pd: [5, 4, 7, 5, 4, 6], bleeding: [MB, DB]}\n"
                           "entries:\n"
                           "  - {site: \"47 ML\", pd: 4, tick: 1200}\n"
                           "diagnosis: {stage: III, extent: localized}\n");
  const Answers a = LoadAnswers(p);
  ASSERT_EQ(a.entries.size(), 7u);
  EXPECT_EQ(a.entries[2].site.ToString(), "46 DB");
  EXPECT_EQ(*a.entries[2].pd_mm, 7);
  EXPECT_TRUE(a.entries[2].bleeding);
  EXPECT_EQ(a.entries[6].tick, 1200u);
  ASSERT_TRUE(a.diagnosis);
  EXPECT_EQ(a.diagnosis->stage, Stage::kIII);
  // What is saved reads back the same.
  SaveAnswers(a, Out("answers_saved.yaml"));
  const Answers b = LoadAnswers(Out("answers_saved.yaml"));
  ASSERT_EQ(b.entries.size(), a.entries.size());
  for (std::size_t i = 0; i < a.entries.size(); ++i) {
    EXPECT_EQ(b.entries[i].site, a.entries[i].site);
    EXPECT_EQ(b.entries[i].pd_mm, a.entries[i].pd_mm);
    EXPECT_EQ(b.entries[i].bleeding, a.entries[i].bleeding);
    EXPECT_EQ(b.entries[i].tick, a.entries[i].tick);
  }
  const fs::path bad = Write("answers_bad.yaml",
                             "chart:\n"
                             "  46: {pd: [5, 4, 7], bleeding: [MX]}\n"
                             "diagnosis: {stage: V, extent: local}\n");
  const std::string f = bad.string();
  EXPECT_EQ(Errors(bad), (std::vector<std::string>{
                             f + ":2:12: 'pd' must be a list of 6 numbers (depths "
                                 "at MB, B, DB, ML, L, DL), found 3",
                             f + ":2:34: unknown site 'MX' (MB, B, DB, ML, L, DL)",
                             f + ":3:20: 'stage' must be I, II, III or IV, not 'V'",
                             f + ":3:31: unknown extent 'local' (expected one of: "
                                 "localized, generalized, molar-incisor)"}));
}

// What no student enters is refused, each with its place: a depth of 0, a site
// given twice without ticks (both lines named); with ticks a later entry is a
// correction and the last wins.
TEST(Answers, ADepthOfZeroAndASiteTwiceAreRefused) {
  const fs::path p = Write("zero_twice.yaml",
                           "chart:\n"
                           "  46: {pd: [3, 3, 3, 3, 3, 3]}\n"
                           "  47: {pd: [3, 0, 3, 3, 3, 3]}\n"
                           "entries:\n"
                           "  - {site: \"45 DB\", pd: 0}\n"
                           "  - {site: \"46 MB\", pd: 4}\n");
  const std::string f = p.string();
  EXPECT_EQ(Errors(p),
            (std::vector<std::string>{
                f + ":3:16: 'pd' is 0 mm, expected 1 to 15",
                f + ":5:25: 'pd' is 0, expected 1 to 15",
                f + ":6:12: site 46 MB is given twice (first at line 2); give it once, "
                    "or give each entry its tick (a later entry is then a correction)"}));
  const Answers corrected =
      LoadAnswers(Write("corrected.yaml",
                        "entries:\n"
                        "  - {site: \"46 MB\", pd: 4, tick: 100}\n"
                        "  - {site: \"46 MB\", pd: 5, tick: 900}\n"));
  ASSERT_EQ(corrected.entries.size(), 2u);
  EXPECT_EQ(*corrected.entries[1].pd_mm, 5);
}

// A diagnosis declares the grade with the stage and extent (A, B or C), and the
// molar-incisor pattern as an extent; saved, it reads back the same.
TEST(Answers, TheDiagnosisCarriesTheGradeAndTheMolarIncisorPattern) {
  const Answers a = LoadAnswers(
      Write("graded.yaml", "diagnosis: {stage: IV, extent: molar-incisor, grade: C}\n"));
  ASSERT_TRUE(a.diagnosis.has_value());
  EXPECT_EQ(a.diagnosis->stage, Stage::kIV);
  EXPECT_EQ(a.diagnosis->extent, Extent::kMolarIncisor);
  EXPECT_EQ(a.diagnosis->grade, Grade::kC);
  EXPECT_EQ(a.diagnosis->Summary(), "periodontitis stage IV, molar-incisor, grade C");
  SaveAnswers(a, Out("graded_again.yaml"));
  const Answers back = LoadAnswers(Out("graded_again.yaml"));
  ASSERT_TRUE(back.diagnosis.has_value());
  EXPECT_EQ(back.diagnosis->grade, Grade::kC);
  EXPECT_EQ(back.diagnosis->extent, Extent::kMolarIncisor);
  const fs::path bad =
      Write("bad_grade.yaml", "diagnosis: {stage: III, extent: localized, grade: D}\n");
  EXPECT_EQ(Errors(bad),
            (std::vector<std::string>{bad.string() +
                                      ":1:51: 'grade' must be A, B or C, not 'D'"}));
}

// Answers meet their lesson: a tooth the lesson does not examine is named with
// its line, whichever form gave it.
TEST(Answers, ATeethOutsideTheLessonIsNamedWithItsLine) {
  const fs::path p = Write("outside.yaml",
                           "chart:\n"
                           "  46: {pd: [3, 3, 3, 3, 3, 3]}\n"
                           "  36: {pd: [3, 3, 3, 3, 3, 3]}\n"
                           "entries:\n"
                           "  - {site: \"11 B\", pd: 2, tick: 5}\n");
  const Answers a = LoadAnswers(p);
  const auto e = test::ErrorLines([&] { CheckAnswersFor(a, {47, 46, 45, 44}); });
  const std::string f = p.string();
  ASSERT_EQ(e.size(), 7u) << ::testing::PrintToString(e);
  EXPECT_EQ(e[0], f + ":3:13: tooth 36 is not in the lesson (its teeth: 47, 46, 45, 44)");
  EXPECT_EQ(e[6], f + ":5:12: tooth 11 is not in the lesson (its teeth: 47, 46, 45, 44)");
  EXPECT_TRUE(test::ErrorLines([&] { CheckAnswersFor(a, {46, 36, 11}); }).empty());
}

}  // namespace
}  // namespace sulcus
