#include "ui/mesh_view.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "core/geometry/primitives.h"

namespace sulcus::ui {
namespace {

namespace fs = std::filesystem;

TEST(MeshView, PolyDataMatchesTheMesh) {
  const TriangleMesh torus = MakeTorus(10, 3, 32, 16);
  const auto poly = ToPolyData(torus);
  EXPECT_EQ(poly->GetNumberOfPoints(), static_cast<vtkIdType>(torus.num_vertices()));
  EXPECT_EQ(poly->GetNumberOfCells(), static_cast<vtkIdType>(torus.num_faces()));
  double p[3];
  poly->GetPoint(5, p);
  EXPECT_DOUBLE_EQ(p[0], torus.vertices()[5].x());  // copied, not computed
}

TEST(MeshView, RendersCalibrationSolidsToPng) {
  const fs::path png = fs::path(SULCUS_TEST_OUTPUT) / "screenshots" / "calibration_solids.png";
  fs::create_directories(png.parent_path());
  TriangleMesh torus = MakeTorus(10, 3, 64, 32);
  TriangleMesh sphere = MakeIcosphere(5, 4);
  sphere.Transform(Matrix3::Identity(), Vector3(0, 0, 8));
  const double drawn = RenderToPng({{&torus, {0.93, 0.91, 0.84}, 1.0},
                                    {&sphere, {0.85, 0.45, 0.45}, 0.6}},
                                   png, 800, 600, "Sulcus calibration solids");
  ASSERT_TRUE(fs::exists(png));
  // The solids fill a good part of the frame once the camera frames them.
  EXPECT_GT(drawn, 0.15);
  EXPECT_LT(drawn, 0.95);
}

}  // namespace
}  // namespace sulcus::ui
