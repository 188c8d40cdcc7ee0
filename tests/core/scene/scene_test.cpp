#include "core/scene/scene.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>

#include "core/anatomy/mesh_contact.h"
#include "core/anatomy/soft_tissue.h"
#include "tests/common/meshes.h"
#include "tests/common/output.h"
#include "tests/core/scene/scene_file_errors.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

using test::Dir;
using test::Errors;
using test::Lines;
using test::Write;

TEST(SceneFile, UnknownKeysSuggestTheNearestOne) {
  EXPECT_EQ(Errors("name: x\nobjets:\n  - tooth: 46\n"),
            (Lines{"2:1: unknown key 'objets' in the scene; did you mean 'objects'?",
                   "1:1: a scene needs 'objects:', a list of teeth, meshes or solids"}));
  EXPECT_EQ(
      Errors("objects:\n  - tooth: 46\n    pocket_mm: [1, 2, 3, 1, 2, 3]\n"),
      (Lines{"3:5: unknown key 'pocket_mm' in an object; did you mean 'pockets_mm'?"}));
}

TEST(SceneFile, WrongTypesAndRanges) {
  EXPECT_EQ(Errors("objects:\n  - tooth: 46\n    pockets_mm: [3, -1, 3, 3, 3, 3]\n"),
            (Lines{"3:21: 'pockets_mm' is -1 mm, expected 0 to 15"}));
  EXPECT_EQ(Errors("objects:\n  - tooth: 46\n    pockets_mm: [3, 3, 3]\n"),
            (Lines{"3:17: 'pockets_mm' must be a list of 6 numbers (depths at MB, B, DB, "
                   "ML, L, DL in mm), found 3"}));
  EXPECT_EQ(Errors("gingiva: joined\nobjects: []\n"),
            (Lines{"1:10: 'gingiva' must be true (a collar around every tooth), arch "
                   "(one gingiva per arch, joined "
                   "between neighbouring teeth) or false"}));
  EXPECT_EQ(Errors("objects:\n  - box: [1, 2]\n    tissue: bone\n"),
            (Lines{"2:10: 'box' must be a list of 3 numbers (sizes along x, y, z in mm), "
                   "found 2"}));
}

TEST(SceneFile, FrictionIsAnEffectWithACoefficientPerObjectAndTextureIsRefused) {
  EXPECT_EQ(Errors("effects: [contact, friction]\nobjects:\n  - box: [1, 1, 1]\n    "
                   "tissue: bone\n    friction: 0.25\n"),
            (Lines{"accepted"}));
  EXPECT_EQ(Errors("objects:\n  - box: [1, 1, 1]\n    tissue: bone\n    friction: 3\n"),
            (Lines{"4:15: 'friction' is 3, expected 0 to 2"}));
  EXPECT_EQ(
      Errors("objects:\n  - box: [1, 1, 1]\n    tissue: bone\n    friction: slippery\n"),
      (Lines{"4:15: 'friction' must be a number, found 'slippery'"}));
  EXPECT_EQ(Errors("effects: [contact, surface_texture]\nobjects:\n  - tooth: 46\n"),
            (Lines{"accepted"}));
}

TEST(SceneFile, ClinicalTruthIsChecked) {
  // Tooth 31's root is 12.5 mm long.
  EXPECT_EQ(Errors("objects:\n  - tooth: 31\n    pockets_mm: [3, 13, 3, 3, 3, 3]\n"),
            (Lines{"3:21: pocket of 13 mm at site B is deeper than the root of tooth 31 "
                   "(12.5 mm)"}));
  EXPECT_EQ(Errors("objects:\n  - tooth: 19\n"),
            (Lines{"2:12: FDI 19 does not exist: the tooth digit is 1 to 8"}));
  EXPECT_EQ(Errors("objects:\n  - tooth: 46\n    bleeding: [MB, BD]\n"),
            (Lines{"3:20: unknown site 'BD'; did you mean 'B'?"}));
  EXPECT_EQ(Errors("objects:\n  - box: [1, 1, 1]\n    tissue: bone\n    pockets_mm: [1, "
                   "1, 1, 1, 1, 1]\n"),
            (Lines{"4:17: 'pockets_mm' is for teeth only"}));
}

TEST(SceneFile, MeshPathsStayInTheSceneFolderAndMustExist) {
  EXPECT_EQ(Errors("objects:\n  - mesh: ../outside.stl\n    tissue: bone\n"),
            (Lines{"2:11: mesh path '../outside.stl' leaves the scene's folder (after "
                   "following links); put the mesh beside the scene file, or name its "
                   "folder in SULCUS_MESH_LIBRARY"}));
  const Lines missing = Errors("objects:\n  - mesh: nope.stl\n    tissue: bone\n");
  ASSERT_EQ(missing.size(), 1u);
  EXPECT_EQ(missing[0].rfind("2:11: mesh path 'nope.stl' not found (looked for ", 0), 0u)
      << missing[0];
}

TEST(SceneFile, AMeshPathMustNameARegularFileInsideTheFolderLinksFollowed) {
  // A link inside the folder to a file outside it is outside.
  const fs::path outside = fs::path(SULCUS_TEST_OUTPUT) / "outside-the-scenes.stl";
  test::WriteTetrahedronStl(outside, 10);
  fs::remove(Dir() / "link_out.stl");
  fs::create_symlink(outside, Dir() / "link_out.stl");
  const Lines linked = Errors("objects:\n  - mesh: link_out.stl\n    tissue: bone\n");
  ASSERT_EQ(linked.size(), 1u);
  EXPECT_NE(linked[0].find("leaves the scene's folder (after following links)"),
            std::string::npos)
      << linked[0];
  // The same link is accepted when the settings name its folder as a library.
  ::setenv("SULCUS_MESH_LIBRARY", outside.parent_path().c_str(), 1);
  EXPECT_EQ(Errors("objects:\n  - mesh: link_out.stl\n    tissue: bone\n"),
            (Lines{"accepted"}));
  ::unsetenv("SULCUS_MESH_LIBRARY");
  // What names no file: empty, the folder itself, a folder, a FIFO, a device,
  // an empty file, a NUL in the name.
  EXPECT_EQ(Errors("objects:\n  - mesh: \"\"\n    tissue: bone\n"),
            (Lines{"2:11: mesh path '' names no file; give the mesh file's name"}));
  EXPECT_EQ(Errors("objects:\n  - mesh: .\n    tissue: bone\n"),
            (Lines{"2:11: mesh path '.' names no file; give the mesh file's name"}));
  fs::create_directories(Dir() / "a_folder.stl");
  EXPECT_EQ(Errors("objects:\n  - mesh: a_folder.stl\n    tissue: bone\n"),
            (Lines{"2:11: mesh path 'a_folder.stl' is a folder, not a file"}));
  fs::remove(Dir() / "fifo.stl");
  ASSERT_EQ(::mkfifo((Dir() / "fifo.stl").c_str(), 0600), 0);
  EXPECT_EQ(Errors("objects:\n  - mesh: fifo.stl\n    tissue: bone\n"),
            (Lines{"2:11: mesh path 'fifo.stl' is not a regular file (a FIFO or a "
                   "device?); give a file"}));
  std::ofstream(Dir() / "empty.stl").flush();
  EXPECT_EQ(Errors("objects:\n  - mesh: empty.stl\n    tissue: bone\n"),
            (Lines{"2:11: mesh path 'empty.stl' is an empty file"}));
  EXPECT_EQ(Errors("objects:\n  - mesh: \"a\\0b.stl\"\n    tissue: bone\n"),
            (Lines{"2:11: mesh path 'a?b.stl' holds a NUL character; give a file name"}));
}

TEST(SceneFile, ARelativeAndAnAbsoluteSpellingOfOneSceneReadItsMeshAlike) {
  test::WriteTetrahedronStl(Dir() / "sibling.stl", 10);
  const fs::path scene =
      Write("sibling_scene.yaml", "objects:\n  - mesh: sibling.stl\n    tissue: bone\n");
  const fs::path before = fs::current_path();
  fs::current_path(Dir());
  std::string relative_error;
  try {
    LoadSceneSpec("sibling_scene.yaml");
  } catch (const LoadError& e) {
    relative_error = e.what();
  }
  fs::current_path(before);
  EXPECT_EQ(relative_error, "");
  EXPECT_NO_THROW(LoadSceneSpec(scene));
  EXPECT_NO_THROW(LoadSceneSpec(Dir() / "." / "sibling_scene.yaml"));
}

TEST(SceneFile, LimitsOfWhatCanBeBuiltAreCheckedAtValidation) {
  const Lines tiny = Errors(
      "objects:\n  - box: [1, 1, 1]\n    tissue: bone\n    spheretree: "
      "{target_error_mm: 0.0001}\n");
  ASSERT_EQ(tiny.size(), 1u);
  EXPECT_NE(tiny[0].find("'target_error_mm' is 0.0001 mm, expected 0.005 to 10"),
            std::string::npos)
      << tiny[0];
  const Lines huge = Errors(
      "objects:\n  - box: [1, 1, 1]\n    tissue: bone\n    spheretree: {levels: 8, "
      "branch: 32, leaves: 1048576}\n");
  ASSERT_EQ(huge.size(), 1u);
  EXPECT_NE(huge[0].find("'leaves' is 1048576, expected 1 to 16384"), std::string::npos)
      << huge[0];
  // A megabyte token is cut in the message, and numbers are printed as %g.
  const Lines long_token = Errors(
      "objects:\n  - box: [1, 1, 1]\n    tissue: " + std::string(1 << 20, 'x') + "\n");
  ASSERT_EQ(long_token.size(), 1u);
  EXPECT_LT(long_token[0].size(), 400u);
  EXPECT_NE(long_token[0].find("... (1048576 characters)"), std::string::npos);
  const Lines big = Errors("objects:\n  - box: [1e308, 1, 1]\n    tissue: bone\n");
  ASSERT_EQ(big.size(), 1u);
  EXPECT_LT(big[0].size(), 200u) << big[0];
}

TEST(SceneBuild, ATreeThatCannotBeBuiltNamesTheSceneItsLineAndTheObject) {
  // A target error that two leaves cannot meet: found only while building.
  const SceneSpec spec = LoadSceneSpec(
      Write("tight_box.yaml",
            "objects:\n  - name: slab\n    box: [40, 40, 40]\n    tissue: bone\n"
            "    spheretree: {levels: 2, branch: 2, target_error_mm: 0.005}\n"));
  try {
    CompileScene(spec, Dir() / "cache-tight", nullptr);
    FAIL() << "two leaves met a 0.005 mm target error";
  } catch (const SphereTreeError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind((Dir() / "tight_box.yaml").string() +
                             ":2: object 'slab': its collision spheres cannot be built: ",
                         0),
              0u)
        << what;
  }
}

// The build's progress is one bar over its phases (meshes, then trees): it
// never runs backwards, and it ends at 1.
TEST(SceneBuild, ProgressRunsOneWayOverMeshesAndTrees) {
  const SceneSpec spec = LoadSceneSpec(
      Write("progress.yaml",
            "spheretree: {levels: 3, leaves: 64}\nobjects:\n  - box: [4, 4, 4]\n    "
            "tissue: bone\n  - sphere: 2\n    at: [10, "
            "0, 0]\n    tissue: bone\n  - cylinder: 1\n    height_mm: 4\n    at: [-10, "
            "0, 0]\n    "
            "tissue: bone\n"));
  std::vector<double> seen;
  std::mutex m;
  CompileScene(spec, test::FreshOutputPath("scenes", "cache-progress"),
               [&](std::string_view, double f) {
                 std::lock_guard lock(m);
                 seen.push_back(f);
                 return true;
               });
  ASSERT_GE(seen.size(), 4u);
  for (std::size_t i = 1; i < seen.size(); ++i)
    EXPECT_GE(seen[i], seen[i - 1] - 1e-12) << "step " << i << " went back";
  EXPECT_NEAR(seen.back(), 1.0, 1e-9);
}

TEST(SceneFile, AMeshFarTooLargeForAMouthIsRefusedBeforeItsTreesAreBuilt) {
  // A tetrahedron 1,000 mm across: a mesh in another unit, or a slipped scale.
  test::WriteTetrahedronStl(Dir() / "huge.stl", 1000);
  const SceneSpec spec = LoadSceneSpec(
      Write("huge_mesh.yaml", "objects:\n  - mesh: huge.stl\n    tissue: bone\n"));
  bool asked = false;
  try {
    CompileScene(spec, Dir() / "cache-huge", [&](std::string_view stage, double) {
      asked |= stage.find("cover") != std::string_view::npos;
      return true;
    });
    FAIL() << "compiled a 1,000 mm mesh";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "huge.stl: is 1732 mm across; a scene object may be at most 300 mm"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(asked) << "refused before any tree was built";
  EXPECT_EQ(Errors("objects:\n  - box: [1000, 1, 1]\n    tissue: bone\n"),
            (Lines{"2:11: 'box' is 1000 mm, expected 0.001 to 200"}));
}

TEST(SceneFile, ManyErrorsAtOnceAndSyntaxErrors) {
  const Lines all = Errors(
      "objects:\n"
      "  - tooth: 99\n"
      "  - box: [1, 1, 1]\n"
      "  - sphere: -2\n"
      "    tissue: bonne\n");
  EXPECT_EQ(all, (Lines{"2:12: FDI 99 does not exist: expected 11 to 48 (quadrant 1 to "
                        "4, then tooth 1 to 8)",
                        "3:5: 'box 2' needs a 'tissue' (enamel, root, gingiva, bone, "
                        "tongue, cheek, palate, lip, "
                        "mucosa, metal, calculus)",
                        "4:13: 'sphere' is -2 mm (a mouth is about 60 mm across), "
                        "expected 0.001 to 100",
                        "5:13: unknown tissue 'bonne'; did you mean 'bone'?"}));
  const Lines syntax = Errors("objects:\n  - tooth: [46\n");
  ASSERT_EQ(syntax.size(), 1u);
  EXPECT_NE(syntax[0].find("YAML syntax:"), std::string::npos) << syntax[0];
  try {
    LoadSceneSpec(Dir() / "missing.yaml");
    ADD_FAILURE();
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("no such scene file"), std::string::npos);
  }
}

TEST(SceneFile, ValuesAreRead) {
  const fs::path p = Write("values_read.yaml",
                           "name: two\n"
                           "haptics: {k_t_n_per_mm: 0.5, rate_hz: 2000}\n"
                           "effects: [tissue_damage]\n"
                           "objects:\n"
                           "  - tooth: 36\n"
                           "    at: [1, 2, 3]\n"
                           "    turn_deg: [0, 0, 90]\n"
                           "    pockets_mm: [1, 2, 3, 4, 5, 6]\n"
                           "    bleeding: [DL]\n"
                           "  - cylinder: 2\n"
                           "    height_mm: 5\n"
                           "    tissue: gingiva\n");
  const SceneSpec s = LoadSceneSpec(p);
  EXPECT_EQ(s.name, "two");
  EXPECT_DOUBLE_EQ(s.haptics.k_t, 0.5);
  EXPECT_DOUBLE_EQ(s.rate_hz, 2000);
  EXPECT_EQ(s.effects, (std::vector<Effect>{Effect::kContact,
                                            Effect::kTissueDamage}));  // contact always
  ASSERT_EQ(s.objects.size(), 2u);
  EXPECT_EQ(s.objects[0].name, "tooth 36");
  EXPECT_NEAR(s.objects[0].X_WO.translation().y(), 2.0, 1e-15);
  EXPECT_NEAR((s.objects[0].X_WO.rotation() * Vector3::UnitX()).y(), 1.0,
              1e-12);  // 90 deg about z
  EXPECT_DOUBLE_EQ(s.objects[0].pocket_mm[5], 6);
  EXPECT_TRUE(s.objects[0].bleeding[5]);
  EXPECT_FALSE(s.objects[0].bleeding[0]);
  EXPECT_EQ(s.objects[1].tissue, Tissue::kGingiva);
  EXPECT_DOUBLE_EQ(s.objects[1].material.damage_limit_n,
                   0.30);  // the gingiva's clinical limit
}

// Trees: the scene's `spheretree` for every object, an object's own over it,
// and `spheretree: gingiva:` for the generated collars (over the scene's).
TEST(SceneFile, SphereTreeSettingsPerObjectAndForTheCollars) {
  const fs::path p = Write("trees.yaml",
                           "spheretree:\n"
                           "  leaves: 256\n"
                           "  gingiva: {levels: 5, leaves: 1024}\n"
                           "arch: true\n"
                           "gingiva: true\n"
                           "objects:\n"
                           "  - tooth: 46\n"
                           "  - tooth: 47\n"
                           "    spheretree: {leaves: 64, levels: 3}\n");
  const SceneSpec s = LoadSceneSpec(p);
  ASSERT_EQ(s.objects.size(), 4u);  // two teeth, two collars
  EXPECT_EQ(s.objects[0].trees.leaves, 256);
  EXPECT_EQ(s.objects[0].trees.levels, 4);
  EXPECT_EQ(s.objects[1].trees.leaves, 64);
  EXPECT_EQ(s.objects[1].trees.levels, 3);
  for (int i : {2, 3}) {
    EXPECT_EQ(s.objects[i].kind, ObjectSpec::Kind::kGingiva);
    EXPECT_EQ(s.objects[i].trees.leaves, 1024);
    EXPECT_EQ(s.objects[i].trees.levels, 5);
  }
  EXPECT_EQ(Errors("spheretree: {leaves: 1024}\nobjects:\n  - tooth: 46\n"),
            (Lines{"1:13: in 'spheretree': 1024 leaves do not fit in 4 levels of 8 (at "
                   "most 512); raise 'levels'"}));
  EXPECT_EQ(Errors("objects:\n  - tooth: 46\n    spheretree: {leafs: 64}\n"),
            (Lines{"3:18: unknown key 'leafs' in an object's 'spheretree'; did you mean "
                   "'leaves'?"}));
  EXPECT_EQ(Errors("spheretree: {gingiva: {gingiva: {}}}\nobjects:\n  - tooth: 46\n"),
            (Lines{"1:24: unknown key 'gingiva' in 'spheretree: gingiva' (expected one "
                   "of: levels, branch, leaves, "
                   "target_error_mm, spend, tighten_passes)"}));
  EXPECT_EQ(Errors("spheretree: {spend: avg}\nobjects:\n  - tooth: 46\n"),
            (Lines{"1:21: in 'spheretree': 'spend' is 'avg' (expected mean or worst)"}));
  const Lines passes =
      Errors("objects:\n  - tooth: 46\n    spheretree: {tighten_passes: 0}\n");
  ASSERT_EQ(passes.size(), 1u);
  EXPECT_NE(passes[0].find("'tighten_passes' is 0, expected 1 to 8"), std::string::npos)
      << passes[0];
}

// What a budget is spent on and how often the leaves are tightened, read for
// the scene, the gingiva and an object, and part of the trees' cache key only
// when not the default (every tree cached before stays found).
TEST(SceneFile, TheSpendAndTheTighteningPassesAreRead) {
  const SceneSpec spec = LoadSceneSpec(
      Write("spend.yaml",
            "spheretree: {spend: worst, gingiva: {leaves: 256, tighten_passes: 1}}\n"
            "gingiva: true\nobjects:\n  - tooth: 46\n"
            "  - box: [2, 2, 2]\n    tissue: bone\n"
            "    spheretree: {spend: mean, tighten_passes: 2}\n"));
  const ObjectSpec* tooth = nullptr;
  const ObjectSpec* gingiva = nullptr;
  const ObjectSpec* box = nullptr;
  for (const ObjectSpec& o : spec.objects) {
    if (o.kind == ObjectSpec::Kind::kTooth) tooth = &o;
    if (o.kind == ObjectSpec::Kind::kGingiva) gingiva = &o;
    if (o.kind == ObjectSpec::Kind::kBox) box = &o;
  }
  ASSERT_TRUE(tooth && gingiva && box);
  EXPECT_EQ(tooth->trees.spend, SphereTreeParams::Spend::kWorst);
  EXPECT_EQ(tooth->trees.tighten_passes, 3);
  EXPECT_EQ(gingiva->trees.spend, SphereTreeParams::Spend::kWorst);
  EXPECT_EQ(gingiva->trees.tighten_passes, 1);
  EXPECT_EQ(gingiva->trees.leaves, 256);
  EXPECT_EQ(box->trees.spend, SphereTreeParams::Spend::kMean);
  EXPECT_EQ(box->trees.tighten_passes, 2);
  EXPECT_EQ(tooth->trees.ToString().find("passes"), std::string::npos);
  EXPECT_NE(gingiva->trees.ToString().find(" passes=1"), std::string::npos);
}

TEST(SceneFile, ShippedScenesValidate) {
  int seen = 0;
  for (const char* folder : {"scenes", "tests/scenes/hard"}) {
    for (const auto& entry :
         fs::directory_iterator(fs::path(SULCUS_SOURCE_DIR) / folder)) {
      if (entry.path().extension() != ".yaml") continue;
      ++seen;
      EXPECT_NO_THROW(LoadSceneSpec(entry.path())) << entry.path();
    }
  }
  EXPECT_GE(seen, 6);
}

TEST(SceneFile, CompilesIntoAnEngineModelThatRuns) {
  const SceneSpec spec =
      LoadSceneSpec(fs::path(SULCUS_SOURCE_DIR) / "tests/scenes/hard/narrow_slot.yaml");
  fs::remove_all(Dir() /
                 "cache");  // an empty cache: every tree is built and reports progress
  int calls = 0;
  const auto scene = CompileScene(spec, Dir() / "cache", [&](std::string_view, double) {
    ++calls;
    return true;
  });
  ASSERT_EQ(scene->trees.size(), 3u);
  EXPECT_GT(calls, 3);
  EXPECT_TRUE(scene->tool_mesh.Check().IsSolid());
  EngineData d(*scene->model);
  // Probe pushed down into the slot: the shaft (1 mm) cannot enter the 0.7 mm gap.
  ResetTool(RigidTransform(Matrix3::Identity(), Vector3(0, 0, 8)), &d);
  for (int i = 0; i < 400; ++i)
    Step(*scene->model, RigidTransform(Matrix3::Identity(), Vector3(0, 0, 8 - 0.03 * i)),
         &d);
  EXPECT_EQ(d.faults.total(), 0u);
  EXPECT_GT(d.force_W.z(), 0.5);  // held up by the walls' tops
  EXPECT_LT(d.max_penetration_mm, 1e-3);
}

}  // namespace
}  // namespace sulcus

namespace sulcus {
namespace {

TEST(SceneFile, ArchGingivaAnatomyCariesAndInflammation) {
  EXPECT_EQ(Errors("arch: maybe\nobjects:\n  - tooth: 46\n"),
            (Lines{"1:7: 'arch' must be true or false"}));
  EXPECT_EQ(Errors("objects:\n  - anatomy: tounge\n"),
            (Lines{"2:14: unknown anatomy 'tounge'; did you mean 'tongue'? (known: "
                   "jaw_lower, jaw_upper, lip_upper, "
                   "lip_lower, cheek_left, cheek_right, tongue, floor_of_mouth, palate, "
                   "soft_palate)"}));
  EXPECT_EQ(Errors("objects:\n  - tooth: 36\n    caries_mm: {ocllusal: 2}\n"),
            (Lines{"3:17: unknown surface 'ocllusal'; did you mean 'occlusal'? (mesial, "
                   "distal, buccal, lingual, "
                   "occlusal)"}));
  EXPECT_EQ(Errors("objects:\n  - tooth: 36\n    inflamed: [MB, XL]\n"),
            (Lines{"3:20: unknown site 'XL'; did you mean 'ML'?"}));
  EXPECT_EQ(Errors("objects:\n  - box: [1, 1, 1]\n    tissue: bone\n    caries_mm: "
                   "{occlusal: 1}\n"),
            (Lines{"4:16: 'caries_mm' is for teeth only"}));
  // A cavity is in a lesion, no deeper than the lesion is wide, and no deeper than 2 mm.
  EXPECT_EQ(
      Errors("objects:\n  - tooth: 36\n    caries_mm: {occlusal: 1.0}\n"
             "    cavity_mm: {occlusal: 1.5, buccal: 0.5, ocllusal: 0.3}\n"),
      (Lines{
          "4:27: a cavity 1.5 mm deep in a lesion of 1.0 mm: the depth is at most the "
          "lesion's size",
          "4:32: a cavity is in a carious lesion: give 'caries_mm' a buccal lesion first",
          "4:45: unknown surface 'ocllusal'; did you mean 'occlusal'? (mesial, distal, "
          "buccal, lingual, "
          "occlusal)"}));
  EXPECT_EQ(Errors("objects:\n  - tooth: 36\n    caries_mm: {occlusal: 4}\n    "
                   "cavity_mm: {occlusal: 3}\n")
                .size(),
            1u)
      << "deeper than 2 mm";
  EXPECT_EQ(
      Errors(
          "gingiva: true\nobjects:\n  - tooth: 31\n    pockets_mm: [2, 2, 2, 2, 2, 2]\n"
          "    recession_mm: [0, 10, 0, 0, 0, 0]\n"),
      (Lines{"3:5: tooth 31: pocket plus recession at site B leaves less than 1 mm of "
             "attached root for the "
             "gingiva"}));

  // Valid: teeth on the arch (lower left and upper right are mirrored), a collar per
  // tooth carrying the tooth's truth, soft tissue with its own tissue type.
  const fs::path p = Write("arch_ok.yaml",
                           "arch: true\ngingiva: true\nobjects:\n  - tooth: 46\n    "
                           "pockets_mm: [5, 4, 7, 5, 4, 6]\n"
                           "    inflamed: [MB]\n    caries_mm: {occlusal: 2.5}\n    "
                           "cavity_mm: {occlusal: 0.8}\n"
                           "  - tooth: 36\n  - anatomy: tongue\n");
  const SceneSpec s = LoadSceneSpec(p);
  ASSERT_EQ(s.objects.size(), 5u);
  EXPECT_FALSE(s.objects[0].mirrored);
  EXPECT_TRUE(s.objects[1].mirrored);
  EXPECT_LT(s.objects[0].X_WO.translation().x(), -15)
      << "46 is on the patient's right (-x)";
  EXPECT_EQ(s.objects[2].tissue, Tissue::kTongue);
  EXPECT_EQ(s.objects[3].kind, ObjectSpec::Kind::kGingiva);
  EXPECT_EQ(s.objects[3].name, "gingiva 46");
  EXPECT_EQ(s.objects[3].pocket_mm[2], 7.0);
  EXPECT_EQ(s.objects[4].pocket_mm[0], 2.0)
      << "a tooth without truth gets healthy 2 mm sulci";
  EXPECT_TRUE(s.objects[0].inflamed[0]);
  EXPECT_EQ(s.objects[0].caries_mm[4], 2.5);
  EXPECT_EQ(s.objects[0].cavity_mm[4], 0.8);
  EXPECT_EQ(s.objects[0].cavity_mm[2], 0.0);
}

TEST(SceneFile, AnUpperToothPlacedByHandStandsCrownDown) {
  const SceneSpec s = LoadSceneSpec(Write(
      "upper_by_hand.yaml",
      "objects:\n  - tooth: 11\n    at: [0, 0, 20]\n  - tooth: 41\n    at: [0, 0, 0]\n"
      "  - tooth: 21\n    at: [9, 0, 20]\n    turn_deg: [0, 0, 0]\n"));
  ASSERT_EQ(s.objects.size(), 3u);
  EXPECT_NEAR(s.objects[0].X_WO.rotation().col(2).z(), -1.0, 1e-12)
      << "11: occlusal down";
  EXPECT_NEAR(s.objects[0].X_WO.rotation().col(1).y(), 1.0, 1e-12)
      << "11: labial still forward";
  EXPECT_NEAR(s.objects[0].X_WO.translation().z(), 20.0, 1e-12)
      << "where the scene put it";
  EXPECT_NEAR(s.objects[1].X_WO.rotation().col(2).z(), 1.0, 1e-12) << "41: occlusal up";
  EXPECT_NEAR(s.objects[2].X_WO.rotation().col(2).z(), 1.0, 1e-12)
      << "21 turned by the scene: as written";
}

TEST(SceneFile, ASoftTissueLesionOnANamedRegion) {
  EXPECT_EQ(
      Errors(
          "objects:\n  - anatomy: tongue\n    lesion: {kind: ulser, region: dorsum}\n"),
      (Lines{"3:20: unknown lesion 'ulser'; did you mean 'ulcer'?"}));
  EXPECT_EQ(Errors("objects:\n  - anatomy: tongue\n    lesion: {kind: ulcer}\n"),
            (Lines{"3:13: a lesion on the tongue needs 'region' (dorsum, "
                   "lateral_border_left, lateral_border_right, "
                   "ventral)"}));
  EXPECT_EQ(Errors("objects:\n  - anatomy: tongue\n    lesion: {kind: ulcer, region: "
                   "lateral_border}\n"),
            (Lines{"3:35: 'tongue' has no region 'lateral_border' (expected one of: "
                   "dorsum, lateral_border_left, "
                   "lateral_border_right, ventral)"}));
  EXPECT_EQ(
      Errors("objects:\n  - anatomy: jaw_lower\n    lesion: {kind: ulcer}\n"),
      (Lines{"3:13: no lesion on 'jaw_lower': it is bone; lesions are for soft tissue"}));
  EXPECT_EQ(Errors("objects:\n  - tooth: 46\n    lesion: {kind: ulcer}\n"),
            (Lines{"3:13: 'lesion' is for soft tissue ('anatomy' objects); a tooth's "
                   "findings are caries_mm and calculus"}));
  const SceneSpec s = LoadSceneSpec(
      Write("lesion_ok.yaml",
            "objects:\n  - anatomy: tongue\n"
            "    lesion: {kind: ulcer, region: lateral_border_left, size_mm: 3}\n"
            "  - anatomy: cheek_right\n    lesion: {kind: leukoplakia}\n"));
  EXPECT_EQ(s.objects[0].lesion_kind, "ulcer");
  EXPECT_EQ(s.objects[0].lesion_region, "lateral_border_left");
  EXPECT_EQ(s.objects[0].lesion_mm, 3.0);
  EXPECT_EQ(s.objects[1].lesion_region, "centre") << "a cheek has one region";
  EXPECT_EQ(s.objects[1].lesion_mm, 2.0) << "the default size";
}

TEST(SceneFile, FurcationByEntranceAndTheBoneBelowIt) {
  EXPECT_EQ(Errors("objects:\n  - tooth: 44\n    furcation: {B: 1}\n"),
            (Lines{"3:16: tooth 44 has one root: no furcation"}));
  EXPECT_EQ(
      Errors("objects:\n  - tooth: 46\n    furcation: {M: 1}\n"),
      (Lines{"3:17: tooth 46 has no furcation entrance 'M' (its entrances: B, L)"}));
  EXPECT_EQ(Errors("objects:\n  - tooth: 16\n    furcation: {B: 4}\n"),
            (Lines{"3:20: 'furcation class' is 4, expected 0 to 3"}));
  EXPECT_EQ(
      Errors("objects:\n  - box: [1, 1, 1]\n    tissue: bone\n    furcation: {B: 1}\n"),
      (Lines{"4:16: 'furcation' is for teeth only"}));
  EXPECT_EQ(FurcationEntrances(16), (std::vector<std::string>{"B", "M", "D"}));
  EXPECT_EQ(FurcationEntrances(24), (std::vector<std::string>{"M", "D"}));
  EXPECT_TRUE(FurcationEntrances(34).empty());
  // Healthy pockets, but class II at 36 B: the jaw's crest drops below the
  // furcation (where 36's roots part, then 1.5 mm more); 35 keeps the healthy 1.5 mm.
  const SceneSpec s = LoadSceneSpec(Write(
      "furcation_ok.yaml",
      "arch: true\nobjects:\n  - tooth: 36\n    pockets_mm: [2, 2, 2, 2, 2, 2]\n"
      "    furcation: {B: 2, L: 1}\n  - tooth: 35\n    pockets_mm: [2, 2, 2, 2, 2, 2]\n"
      "  - anatomy: jaw_lower\n"));
  EXPECT_EQ(s.objects[0].furcation.at("B"), 2);
  EXPECT_EQ(s.objects[0].furcation.at("L"), 1);
  EXPECT_GT(FurcationRoofMm(36), 3.0);
  EXPECT_LT(FurcationRoofMm(36), 5.0);
  EXPECT_DOUBLE_EQ(s.objects[2].crest_drop_mm.at(36), FurcationRoofMm(36) + 1.5);
  EXPECT_EQ(s.objects[2].furcation_of.at(36), s.objects[0].furcation);
  EXPECT_DOUBLE_EQ(s.objects[2].crest_drop_mm.at(35), 1.5);
  // That jaw gets a finer tree than the scene's default, so that a probe
  // feels the defect; one that names its own keeps it; a jaw without a
  // defect (class 0 only) keeps the scene's.
  EXPECT_EQ(s.objects[2].trees.leaves, kFurcationJawLeaves);
  EXPECT_EQ(s.objects[2].trees.levels, 5);
  EXPECT_EQ(s.objects[2].trees.spend, SphereTreeParams::Spend::kWorst);
  EXPECT_EQ(s.objects[2].trees.tighten_passes, kFurcationJawTightenPasses);
  const SceneSpec own =
      LoadSceneSpec(Write("furcation_own_tree.yaml",
                          "arch: true\nobjects:\n  - tooth: 36\n    furcation: {B: 2}\n"
                          "  - anatomy: jaw_lower\n    spheretree: {leaves: 256}\n"));
  EXPECT_EQ(own.objects[1].trees.leaves, 256);
  const SceneSpec none =
      LoadSceneSpec(Write("furcation_none.yaml",
                          "arch: true\nobjects:\n  - tooth: 36\n    furcation: {B: 0}\n"
                          "  - anatomy: jaw_lower\n"));
  EXPECT_EQ(none.objects[1].trees.leaves, SphereTreeParams{}.leaves);
  // Deep pockets at a molar and no class: the bone between its roots is
  // modelled whole (its crest below the furcation), and the jaw is as fine;
  // the other jaw is not.
  const SceneSpec deep = LoadSceneSpec(
      Write("furcation_deep.yaml",
            "arch: true\nobjects:\n  - tooth: 36\n    pockets_mm: [6, 5, 6, 5, 4, 5]\n"
            "  - anatomy: jaw_lower\n  - anatomy: jaw_upper\n"));
  EXPECT_GT(deep.objects[1].crest_drop_mm.at(36), FurcationRoofMm(36));
  EXPECT_EQ(deep.objects[1].trees.leaves, kFurcationJawLeaves);
  EXPECT_EQ(deep.objects[2].trees.leaves, SphereTreeParams{}.leaves);
}

TEST(SceneFile, CalculusBySiteAboveOrBelowTheMargin) {
  EXPECT_EQ(Errors("objects:\n  - tooth: 31\n    calculus: [L]\n"),
            (Lines{"3:15: 'calculus' must map 'supra' and 'sub' to lists of sites, e.g. "
                   "{supra: [L], sub: [MB]}"}));
  EXPECT_EQ(Errors("objects:\n  - tooth: 31\n    calculus: {supra: [L], subb: [MB]}\n"),
            (Lines{"3:28: unknown calculus position 'subb'; did you mean 'sub'? (supra: "
                   "above the gingival margin, "
                   "sub: in the sulcus)"}));
  EXPECT_EQ(Errors("objects:\n  - tooth: 31\n    calculus: {supra: [L], sub: [L]}\n"),
            (Lines{"3:34: site L has calculus named twice"}));
  EXPECT_EQ(Errors("objects:\n  - tooth: 31\n    calculus: {supra: [LL]}\n"),
            (Lines{"3:24: unknown site 'LL'; did you mean 'ML'?"}));
  EXPECT_EQ(
      Errors("objects:\n  - sphere: 2\n    tissue: bone\n    calculus: {supra: [L]}\n"),
      (Lines{"4:15: 'calculus' is for teeth only"}));
  // A deposit object per site, on its tooth, named for it; hard.
  const SceneSpec s =
      LoadSceneSpec(Write("calculus_ok.yaml",
                          "arch: true\ngingiva: true\nobjects:\n  - tooth: 31\n"
                          "    calculus: {supra: [L, DL], sub: [MB]}\n"));
  std::vector<std::string> names;
  for (const ObjectSpec& o : s.objects) {
    if (o.kind != ObjectSpec::Kind::kCalculus) continue;
    names.push_back(o.name);
    EXPECT_EQ(o.tissue, Tissue::kCalculus);
    EXPECT_EQ(o.fdi, 31);
    EXPECT_TRUE(o.with_gingiva);
    EXPECT_EQ(o.X_WO.translation(), s.objects[0].X_WO.translation());
  }
  EXPECT_EQ(names, (std::vector<std::string>{"calculus 31 MB", "calculus 31 L",
                                             "calculus 31 DL"}));
}

}  // namespace
}  // namespace sulcus

namespace sulcus {
namespace {

TEST(SceneEvents, DescribedWithTheScenesNames) {
  SceneSpec spec;
  spec.objects.resize(1);
  spec.objects[0].name = "tooth 46";
  HapticEvent e = HapticEvent::Of(EventKind::kProbeReading, 0);
  e.payload.reading = {.fdi = 46,
                       .site = 1,
                       .depth_mm = 3.85,
                       .peak_force_n = 0.223,
                       .axis_angle_deg = 4.2};
  EXPECT_EQ(DescribeEvent(spec, e), "reading 3.9 mm at 46 B (0.22 N, 4 deg)");
  e.kind = EventKind::kContactBegan;
  EXPECT_EQ(DescribeEvent(spec, e), "touching tooth 46");
  e.object = 7;
  EXPECT_EQ(DescribeEvent(spec, e), "touching object 7");
  e.kind = EventKind::kForceAbove;
  e.payload.force.force_n = 1.014;
  EXPECT_EQ(DescribeEvent(spec, e), "force above 1.01 N");
  e.kind = EventKind::kCommand;
  e.payload.command.command = static_cast<std::uint8_t>(HapticCommand::Kind::kPause);
  EXPECT_EQ(DescribeEvent(spec, e), "command: pause");
  e = HapticEvent::Of(EventKind::kProbeReading, 0);
  e.payload.reading = {
      .fdi = 46, .site = 2, .depth_mm = 7.4, .peak_force_n = 1.66, .axis_angle_deg = 3};
  EXPECT_EQ(DescribeEvent(spec, e),
            "reading 7.4 mm at 46 DB (1.66 N, 3 deg): too hard, the tip went into the "
            "attachment (tissue damage)");
}

}  // namespace
}  // namespace sulcus

namespace sulcus {
namespace {

TEST(SceneFile, GingivaArchJoinsNeighboursOnly) {
  const std::string teeth =
      "arch: true\nobjects:\n  - tooth: 44\n  - tooth: 45\n  - tooth: 46\n  - tooth: "
      "41\n";
  auto neighbours = [&](const std::string& gingiva) {
    const SceneSpec s = LoadSceneSpec(
        Write("GingivaArch_" + gingiva, "gingiva: " + gingiva + "\n" + teeth));
    std::map<int, std::vector<int>> out;
    for (const ObjectSpec& o : s.objects)
      if (o.kind == ObjectSpec::Kind::kGingiva)
        for (const GingivaNeighbourSpec& n : o.gingiva_neighbours)
          out[o.fdi].push_back(n.fdi);
    return out;
  };
  const auto joined = neighbours("arch");
  EXPECT_EQ(joined.at(44), std::vector<int>{45});
  EXPECT_EQ(joined.at(45), (std::vector<int>{44, 46}));
  EXPECT_EQ(joined.at(46), std::vector<int>{45});
  EXPECT_EQ(joined.count(41), 0u) << "41 has no neighbour in the scene";
  EXPECT_TRUE(neighbours("true").empty()) << "collars stay collars";
}

// A tooth on the patient's left is its twin on the right, mirrored: its tree
// is the twin's, mirrored (one build for the two, through the cache), and it
// covers its own mesh.
TEST(SceneCompile, AMirroredToothGetsItsTwinsTreeMirrored) {
  const fs::path cache = Dir() / "cache-mirror";
  fs::remove_all(cache);
  const SceneSpec spec = LoadSceneSpec(
      Write("mirror_twins.yaml", "arch: true\nobjects:\n  - tooth: 44\n  - tooth: 34\n"));
  const auto scene = CompileScene(spec, cache);
  int right = -1, left = -1;
  for (int i = 0; i < static_cast<int>(scene->spec.objects.size()); ++i) {
    const ObjectSpec& o = scene->spec.objects[i];
    if (o.kind != ObjectSpec::Kind::kTooth) continue;
    (o.fdi == 44 ? right : left) = i;
  }
  ASSERT_GE(right, 0);
  ASSERT_GE(left, 0);
  ASSERT_NE(scene->spec.objects[right].mirrored, scene->spec.objects[left].mirrored);
  const SphereTree& a = scene->trees[right];
  const SphereTree& b = scene->trees[left];
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t n = 0; n < a.size(); ++n) {
    EXPECT_EQ(a.x[n], -b.x[n]);
    EXPECT_EQ(a.y[n], b.y[n]);
    EXPECT_EQ(a.z[n], b.z[n]);
    EXPECT_EQ(a.r[n], b.r[n]);
  }
  // Every vertex of each tooth's own (mirrored or not) mesh lies in a leaf.
  for (const int i : {right, left}) {
    const SphereTree& t = scene->trees[i];
    for (const Vector3& v : scene->meshes[i].vertices()) {
      bool inside = false;
      for (std::size_t n = 0; n < t.size() && !inside; ++n)
        inside = t.IsLeaf(n) && (v - t.center(n)).norm() <= t.r[n] + 1e-6;
      ASSERT_TRUE(inside) << scene->spec.objects[i].name << " vertex " << v.transpose();
    }
  }
  // One build: the cache holds the tool's tree and one tooth tree, not two.
  int trees = 0;
  for (const auto& f : fs::directory_iterator(cache))
    trees += f.path().filename().string().rfind("tree-", 0) == 0;
  EXPECT_EQ(trees, 2);
}

}  // namespace
}  // namespace sulcus
