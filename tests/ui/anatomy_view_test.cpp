// Pictures of the generated teeth: look at them. Saved under
// build/<preset>/test-output/screenshots/.

#include <gtest/gtest.h>

#include <filesystem>

#include "core/anatomy/arch.h"
#include "core/anatomy/probe.h"
#include "core/anatomy/tooth.h"
#include "ui/mesh_view.h"
#include "tests/common/output.h"

namespace sulcus::ui {
namespace {

namespace fs = std::filesystem;

fs::path Shot(const std::string& name) { return test::OutputPath("screenshots", name); }

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
  const double drawn = RenderToPng({{&lower.mesh, {0.93, 0.91, 0.84}, 1.0}, {&upper.mesh, {0.93, 0.91, 0.84}, 1.0}},
                                   Shot("molars_36_26.png"), 1000, 700, "Generated molars 36 (2 roots) and 26 (3 roots)");
  EXPECT_GT(drawn, 0.1);
}

TEST(AnatomyView, ProbeAtAMolar) {
  ToothModel tooth = GenerateTooth(46);
  const ProbeModel probe = MakeProbe("williams");
  TriangleMesh p = probe.mesh;
  // The tip at the buccal cervix, the working end along the tooth's long axis.
  p.Transform(Matrix3::Identity(), Vector3(0, 5.6, -1.0));
  const double drawn = RenderToPng({{&tooth.mesh, {0.93, 0.91, 0.84}, 1.0}, {&p, {0.75, 0.78, 0.82}, 1.0}},
                                   Shot("probe_at_46.png"), 1000, 800, "Williams probe at tooth 46");
  EXPECT_GT(drawn, 0.02);  // a 100 mm probe beside a 21 mm tooth: the frame is mostly background
}

TEST(AnatomyView, LowerArch) {
  std::vector<TriangleMesh> teeth;
  for (const PlacedTooth& p : PlaceArch(false)) teeth.push_back(PlacedMesh(p, GenerateTooth(p.tooth.fdi).mesh));
  std::vector<ShadedMesh> shaded;
  for (const TriangleMesh& t : teeth) shaded.push_back({&t, {0.93, 0.91, 0.84}, 1.0});
  const double drawn = RenderToPng(shaded, Shot("lower_arch.png"), 1200, 800, "Generated lower arch, 37 to 47");
  EXPECT_GT(drawn, 0.1);
}

}  // namespace
}  // namespace sulcus::ui
