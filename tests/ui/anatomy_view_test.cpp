// Pictures of the generated teeth: look at them. Saved under
// build/<preset>/test-output/screenshots/.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "core/anatomy/arch.h"
#include "core/anatomy/mesh_clip.h"
#include "core/anatomy/probe.h"
#include "core/anatomy/soft_tissue.h"
#include "core/anatomy/tooth.h"
#include "core/scene/scene.h"
#include "tests/common/output.h"
#include "ui/mesh_view.h"

namespace sulcus::ui {
namespace {

namespace fs = std::filesystem;

fs::path Shot(const std::string& name) { return test::OutputPath("screenshots", name); }
using test::OutputPath;

// RenderToPng's camera is raised 25 degrees and turned 35. `R` turns the
// meshes so that its rows are the image's x, y (up) and z (toward the
// camera); turned back after it, so that the camera looks straight along -z.
Matrix3 Straight(const Matrix3& R) {
  return Matrix3(Eigen::AngleAxisd(35 * M_PI / 180, Vector3::UnitY())) *
         Matrix3(Eigen::AngleAxisd(-25 * M_PI / 180, Vector3::UnitX())) * R;
}

// The mouth (+x the patient's left, +y forward, +z occlusal) seen straight
// from in front, the camera `below_deg` below the occlusal plane (negative:
// above it).
Matrix3 FromTheFront(double below_deg) {
  const double e = below_deg * M_PI / 180;
  Matrix3 R;
  R << -1, 0, 0, 0, -std::sin(e), std::cos(e), 0, std::cos(e), std::sin(e);
  return Straight(R);
}

TEST(AnatomyView, LowerRightQuadrantRow) {
  std::vector<TriangleMesh> teeth;
  double x = 0;
  for (int fdi = 41; fdi <= 47; ++fdi) {
    ToothModel m = GenerateTooth(fdi);
    const double half = m.dimensions.md_crown / 2;
    x += half;
    // Side by side, long axes up and buccal faces toward the camera (+z).
    const Matrix3 R = Eigen::AngleAxisd(-M_PI / 2, Vector3::UnitX()).toRotationMatrix() *
                      Eigen::AngleAxisd(M_PI, Vector3::UnitZ()).toRotationMatrix();
    m.mesh.Transform(R, Vector3(x, 0, 0));
    x += half + 0.5;
    teeth.push_back(std::move(m.mesh));
  }
  std::vector<ShadedMesh> shaded;
  for (const TriangleMesh& t : teeth) shaded.push_back({&t, {0.93, 0.91, 0.84}, 1.0});
  const double drawn = RenderToPng(shaded, Shot("teeth_41_to_47.png"), 1200, 600,
                                   "Generated teeth 41-47 (lower right), buccal view");
  EXPECT_GT(drawn, 0.1);
}

TEST(AnatomyView, MolarsUpperAndLower) {
  ToothModel lower = GenerateTooth(36);
  ToothModel upper = GenerateTooth(26);
  upper.mesh.Transform(Matrix3::Identity(), Vector3(14, 0, 0));
  const double drawn = RenderToPng(
      {{&lower.mesh, {0.93, 0.91, 0.84}, 1.0}, {&upper.mesh, {0.93, 0.91, 0.84}, 1.0}},
      Shot("molars_36_26.png"), 1000, 700,
      "Generated molars 36 (2 roots) and 26 (3 roots)");
  EXPECT_GT(drawn, 0.1);
}

TEST(AnatomyView, ProbeAtAMolar) {
  ToothModel tooth = GenerateTooth(46);
  const ProbeModel probe = MakeProbe("williams");
  TriangleMesh p = probe.mesh;
  // The tip at the buccal cervix, the working end along the tooth's long axis.
  p.Transform(Matrix3::Identity(), Vector3(0, 5.6, -1.0));
  const double drawn =
      RenderToPng({{&tooth.mesh, {0.93, 0.91, 0.84}, 1.0}, {&p, {0.75, 0.78, 0.82}, 1.0}},
                  Shot("probe_at_46.png"), 1000, 800, "Williams probe at tooth 46");
  EXPECT_GT(drawn,
            0.02);  // a 100 mm probe beside a 21 mm tooth: the frame is mostly background
}

TEST(AnatomyView, LowerArch) {
  std::vector<TriangleMesh> teeth;
  for (const PlacedTooth& p : PlaceArch(false))
    teeth.push_back(PlacedMesh(p, GenerateTooth(p.tooth.fdi).mesh));
  std::vector<ShadedMesh> shaded;
  for (const TriangleMesh& t : teeth) shaded.push_back({&t, {0.93, 0.91, 0.84}, 1.0});
  const double drawn = RenderToPng(shaded, Shot("lower_arch.png"), 1200, 800,
                                   "Generated lower arch, 37 to 47");
  EXPECT_GT(drawn, 0.1);
}

// The tongue in the lower arch with the floor of the mouth, from in front and
// above (as an examiner sees it with the mouth open), and from the side.
TEST(AnatomyView, TongueInTheLowerArch) {
  std::vector<TriangleMesh> meshes;
  for (const PlacedTooth& p : PlaceArch(false))
    meshes.push_back(PlacedMesh(p, GenerateTooth(p.tooth.fdi).mesh));
  const std::size_t teeth = meshes.size();
  meshes.push_back(MakeSoftTissue("tongue"));
  meshes.push_back(MakeSoftTissue("floor_of_mouth"));
  for (const char* view : {"front", "side"}) {
    std::vector<TriangleMesh> turned = meshes;
    // RenderToPng looks from above (+z), tilted; turn the mouth so that its
    // front (-y is back) faces the camera, or its right side.
    // Rows: where the image's x, y (up) and z (toward the camera) point in the
    // mouth (+y forward, +z occlusal). From the front 50 degrees above the
    // occlusal plane, or from the patient's left.
    const double e = 50 * M_PI / 180;
    Matrix3 R;
    if (std::string(view) == "front") {
      R << -1, 0, 0, 0, -std::sin(e), std::cos(e), 0, std::cos(e), std::sin(e);
    } else {
      R << 0, -1, 0, 0, 0, 1, -1, 0, 0;
    }
    for (TriangleMesh& m : turned) m.Transform(R, Vector3::Zero());
    std::vector<ShadedMesh> shaded;
    for (std::size_t i = 0; i < turned.size(); ++i)
      shaded.push_back({&turned[i], {0.93, 0.91, 0.84}, 1.0});
    for (std::size_t i = teeth; i < turned.size(); ++i) {
      shaded[i].color[0] = 0.85, shaded[i].color[1] = 0.45, shaded[i].color[2] = 0.48;
    }
    const double drawn = RenderToPng(
        shaded, Shot(std::string("tongue_") + view + ".png"), 1000, 800,
        std::string("Tongue and floor of the mouth in the lower arch, ") + view);
    EXPECT_GT(drawn, 0.1);
  }
}

// Both arches, the mouth opened 20 mm, with the lips and cheeks, from in front.
TEST(AnatomyView, LipsAndCheeksAroundTheOpenMouth) {
  const ArchParams open{.upper_lift_mm = 20};
  std::vector<TriangleMesh> meshes;
  for (bool upper : {false, true})
    for (const PlacedTooth& p : PlaceArch(upper, open))
      meshes.push_back(PlacedMesh(p, GenerateTooth(p.tooth.fdi).mesh));
  const std::size_t teeth = meshes.size();
  for (const char* name :
       {"lip_upper", "lip_lower", "cheek_left", "cheek_right", "tongue"})
    meshes.push_back(MakeSoftTissue(name, open));
  // From in front, 10 degrees above the occlusal plane.
  const Matrix3 R = FromTheFront(-10);
  for (TriangleMesh& m : meshes) m.Transform(R, Vector3::Zero());
  std::vector<ShadedMesh> shaded;
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    shaded.push_back({&meshes[i], {0.93, 0.91, 0.84}, 1.0});
    if (i >= teeth)
      shaded.back().color[0] = 0.85, shaded.back().color[1] = 0.5,
      shaded.back().color[2] = 0.52;
  }
  const double drawn = RenderToPng(shaded, Shot("lips_front.png"), 1000, 800,
                                   "Lips, cheeks and tongue, mouth open 20 mm");
  EXPECT_GT(drawn, 0.1);
}

// Tooth 46 in its jaw from the buccal side with its buccal furcation class 1,
// 2 and 3 (left to right; the crest where the scene's rule puts it), the jaw
// cut to the tooth's neighbourhood.
TEST(AnatomyView, FurcationClasses) {
  const std::vector<PlacedTooth> placed = PlaceArch(false);
  const PlacedTooth p =
      *std::find_if(placed.begin(), placed.end(),
                    [](const PlacedTooth& t) { return t.tooth.fdi == 46; });
  const RigidTransform X_TW = p.X_WT.inverse();
  const double roof = FurcationRoofMm(46);
  const double below[4] = {0, 0.5, 1.5, 3.0};
  // Rows: the image's x, y (up) and z (toward the camera) in the tooth frame
  // (+y buccal, +z toward the crown).
  // The camera straight at the buccal side.
  Matrix3 R;
  R << -1, 0, 0, 0, 0, 1, 0, 1, 0;
  R = Straight(R);
  std::vector<TriangleMesh> meshes;
  for (int hamp = 1; hamp <= 3; ++hamp) {
    TriangleMesh jaw = MakeSoftTissue("jaw_lower", {}, {{46, roof + below[hamp]}},
                                      {{46, {{"B", hamp}, {"L", 0}}}});
    jaw.Transform(X_TW.rotation(), X_TW.translation());
    jaw = ClipByPlanes(jaw, {{Vector3(6.5, 0, 0), Vector3::UnitX()},
                             {Vector3(-6.5, 0, 0), -Vector3::UnitX()},
                             {Vector3(0, 12, 0), Vector3::UnitY()},
                             {Vector3(0, -12, 0), -Vector3::UnitY()},
                             {Vector3(0, 0, -11), -Vector3::UnitZ()}});
    TriangleMesh tooth = GenerateTooth(46).mesh;
    for (TriangleMesh* m : {&jaw, &tooth}) {
      m->Transform(Matrix3::Identity(), Vector3(-15.0 * (hamp - 2), 0, 0));
      m->Transform(R, Vector3::Zero());
      meshes.push_back(std::move(*m));
    }
  }
  std::vector<ShadedMesh> shaded;
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    shaded.push_back({&meshes[i], {0.93, 0.91, 0.84}, 1.0});
    if (i % 2 == 0)
      shaded.back().color[0] = 0.9, shaded.back().color[1] = 0.82,
      shaded.back().color[2] = 0.7;  // bone
  }
  const double drawn = RenderToPng(shaded, Shot("furcation_classes.png"), 1200, 600,
                                   "46 from the buccal side: furcation class I, II, III "
                                   "(bone 0.5, 1.5, 3 mm below the entrance)");
  EXPECT_GT(drawn, 0.1);
}

// The upper front teeth, 13 to 23, in their gingiva and jaw as the oral
// inspection scene builds them, from in front and a little below, close: the
// papillae between the incisors and the scalloped margin.
TEST(AnatomyView, GingivaOfTheUpperFront) {
  const SceneSpec spec =
      LoadSceneSpec(fs::path(SULCUS_SOURCE_DIR) / "scenes" / "oral_inspection.yaml");
  const fs::path cache = OutputPath("cache");
  std::vector<TriangleMesh> meshes;
  std::vector<std::vector<Vector3>>
      normals;             // (the shares': drawn with them, as the scene view draws them)
  std::vector<int> kinds;  // 0 tooth, 1 gingiva or jaw
  // From in front, 5 degrees below the occlusal plane: looking a little up
  // at the upper teeth.
  const Matrix3 R = FromTheFront(5);
  for (const ObjectSpec& o : spec.objects) {
    const bool front = o.fdi == 13 || o.fdi == 12 || o.fdi == 11 || o.fdi == 21 ||
                       o.fdi == 22 || o.fdi == 23;
    const bool tooth = o.kind == ObjectSpec::Kind::kTooth,
               gingiva = o.kind == ObjectSpec::Kind::kGingiva;
    if (!((tooth || gingiva) && front) && o.anatomy != "jaw_upper") continue;
    std::vector<Vector3> n;
    TriangleMesh m = MakeObjectMeshCached(o, cache, &n, /*seen=*/true);
    for (Vector3& v : n) v = R * o.X_WO.rotation() * v;
    normals.push_back(std::move(n));
    m.Transform(o.X_WO.rotation(), o.X_WO.translation());
    if (o.anatomy == "jaw_upper")  // (its front only)
      m = ClipByPlanes(m, {{Vector3(0, -8, 0), -Vector3::UnitY()}});
    meshes.push_back(std::move(m));
    kinds.push_back(tooth ? 0 : 1);
  }
  ASSERT_EQ(meshes.size(), 13u)
      << "six teeth, their six shares of the gingiva and the upper jaw";
  EXPECT_EQ(std::count_if(normals.begin(), normals.end(),
                          [](const auto& n) { return !n.empty(); }),
            6)
      << "each share of the gingiva has its normals";
  for (TriangleMesh& m : meshes) m.Transform(R, Vector3::Zero());
  std::vector<ShadedMesh> shaded;
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    // (with the scene view's crease angle: a share's flat cut against its
    // neighbour stays sharp instead of darkening the seam)
    shaded.push_back({&meshes[i],
                      {0.93, 0.91, 0.84},
                      1.0,
                      normals[i].empty() ? nullptr : &normals[i],
                      kCreaseDeg});
    if (kinds[i] == 1)
      shaded.back().color[0] = 0.85, shaded.back().color[1] = 0.5,
      shaded.back().color[2] = 0.52;
  }
  const double drawn =
      RenderToPng(shaded, Shot("gingiva_upper_front.png"), 1200, 800,
                  "Upper front teeth 13 to 23 in their gingiva, from in front");
  EXPECT_GT(drawn, 0.1);
}

}  // namespace
}  // namespace sulcus::ui
