#include "ui/mesh_view.h"

#include <gtest/gtest.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>

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

TEST(MeshView, GivenNormalsAreDrawnWhereTheyFitTheFaces) {
  // An icosphere (coarse: its faces' normals are far from the sphere's) with
  // the exact sphere's normals given: each point takes its vertex's given
  // normal. Given normals that turn away from a face (more than the crease
  // angle) are not used there; a zero normal counts as none.
  const TriangleMesh sphere = MakeIcosphere(5, 1);
  std::vector<Vector3> exact;
  for (const Vector3& v : sphere.vertices()) exact.push_back(v.normalized());
  const auto poly = ToPolyData(sphere, 60, &exact);
  ASSERT_EQ(poly->GetNumberOfPoints(), static_cast<vtkIdType>(sphere.num_vertices()));
  // (points are made corner by corner: the source array names each one's vertex)
  auto source = [](vtkPolyData* p, vtkIdType i) {
    return static_cast<std::size_t>(
        p->GetPointData()->GetArray(kSourceVertexArray)->GetTuple1(i));
  };
  double n[3];
  for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i) {
    poly->GetPointData()->GetNormals()->GetTuple(i, n);
    EXPECT_NEAR(Vector3(n[0], n[1], n[2]).dot(exact[source(poly, i)]), 1.0, 1e-12) << i;
  }
  std::vector<Vector3> wrong(exact.size(), Vector3::Zero());
  wrong[0] = -exact[0];  // inward: more than 60 degrees from every face around it
  const auto fallback = ToPolyData(sphere, 60, &wrong);
  int checked = 0;
  for (vtkIdType i = 0; i < fallback->GetNumberOfPoints(); ++i) {
    fallback->GetPointData()->GetNormals()->GetTuple(i, n);
    const std::size_t v = source(fallback, i);
    EXPECT_GT(Vector3(n[0], n[1], n[2]).dot(exact[v]), 0.9)
        << "drawn from its faces: " << v;
    checked += v == 0;
  }
  EXPECT_EQ(checked, 1);
  // Without a crease angle (one point a vertex) the given normals are used as they are.
  const auto plain = ToPolyData(sphere, 0, &exact);
  ASSERT_EQ(plain->GetNumberOfPoints(), static_cast<vtkIdType>(sphere.num_vertices()));
  for (vtkIdType i = 0; i < plain->GetNumberOfPoints(); ++i) {
    plain->GetPointData()->GetNormals()->GetTuple(i, n);
    EXPECT_NEAR(Vector3(n[0], n[1], n[2]).dot(exact[i]), 1.0, 1e-12) << i;
  }
}

TEST(MeshView, RendersCalibrationSolidsToPng) {
  const fs::path png =
      fs::path(SULCUS_TEST_OUTPUT) / "screenshots" / "calibration_solids.png";
  fs::create_directories(png.parent_path());
  TriangleMesh torus = MakeTorus(10, 3, 64, 32);
  TriangleMesh sphere = MakeIcosphere(5, 4);
  sphere.Transform(Matrix3::Identity(), Vector3(0, 0, 8));
  const double drawn =
      RenderToPng({{&torus, {0.93, 0.91, 0.84}, 1.0}, {&sphere, {0.85, 0.45, 0.45}, 0.6}},
                  png, 800, 600, "Sulcus calibration solids");
  ASSERT_TRUE(fs::exists(png));
  // The solids fill a good part of the frame once the camera frames them.
  EXPECT_GT(drawn, 0.15);
  EXPECT_LT(drawn, 0.95);
}

}  // namespace
}  // namespace sulcus::ui
