// A generated case saved as a scene of its own: the lesson's scene with its
// teeth's pockets, recession and bleeding replaced, read back to the same true
// chart and classification, usable by a lesson without `case:`.
#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "core/lesson/lesson_spec.h"
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

}  // namespace
}  // namespace sulcus
