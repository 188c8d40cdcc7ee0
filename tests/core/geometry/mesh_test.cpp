#include "core/geometry/mesh.h"

#include <gtest/gtest.h>

#include <numbers>

#include "core/geometry/primitives.h"
#include "tests/common/compare.h"

namespace sulcus {
namespace {

using test::CompareMatrices;
using test::CompareScalars;
using test::ToleranceType;
constexpr double kPi = std::numbers::pi;

TEST(Mesh, BoxIsAValidSolidWithExactMeasures) {
  const TriangleMesh box = MakeBox(Vector3(2, 3, 4), 3);
  const MeshReport r = box.Check();
  EXPECT_TRUE(r.IsSolid());
  EXPECT_EQ(r.num_faces, 6u * 9 * 2);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_TRUE(
      CompareScalars(r.volume, 24.0, test::tol::kAccumulated, ToleranceType::kRelative));
  EXPECT_TRUE(CompareScalars(r.area, 2 * (6 + 8 + 12), test::tol::kAccumulated,
                             ToleranceType::kRelative));
  EXPECT_TRUE(CompareMatrices(r.bounds.min, Vector3(-1, -1.5, -2), 1e-15));
  EXPECT_TRUE(CompareMatrices(r.bounds.max, Vector3(1, 1.5, 2), 1e-15));
}

TEST(Mesh, IcosphereConvergesToTheSphere) {
  const TriangleMesh s = MakeIcosphere(5.0, 5);
  const MeshReport r = s.Check();
  EXPECT_TRUE(r.IsSolid());
  // Inscribed polyhedron of 20480 faces: volume and area within 0.2 % below exact.
  const double v = 4.0 / 3.0 * kPi * 125, a = 4 * kPi * 25;
  EXPECT_LT(r.volume, v);
  EXPECT_GT(r.volume, 0.998 * v);
  EXPECT_LT(r.area, a);
  EXPECT_GT(r.area, 0.998 * a);
}

TEST(Mesh, TorusHasGenusOne) {
  const MeshReport r = MakeTorus(10, 3, 48, 24).Check();
  EXPECT_TRUE(r.IsSolid());
  EXPECT_EQ(r.euler_characteristic, 0);  // 2 - 2g with g = 1
  // Volume 2 pi^2 R r^2 for the smooth torus; the polygonal one is a little less.
  EXPECT_NEAR(r.volume / (2 * kPi * kPi * 10 * 9), 1.0, 0.02);
}

TEST(Mesh, CylinderIsAValidSolid) {
  const MeshReport r = MakeCylinder(2, 10, 64, 4).Check();
  EXPECT_TRUE(r.IsSolid());
  EXPECT_NEAR(r.volume / (kPi * 4 * 10), 1.0, 0.01);
}

TEST(Mesh, InwardNormalsAreReported) {
  TriangleMesh box = MakeBox(Vector3(1, 1, 1));
  box.FlipOrientation();
  const MeshReport r = box.Check();
  EXPECT_TRUE(r.closed());
  EXPECT_TRUE(r.oriented());
  EXPECT_FALSE(r.outward());
  EXPECT_FALSE(r.IsSolid());
  EXPECT_TRUE(CompareScalars(r.volume, -1.0, 1e-14));
}

TEST(Mesh, OneFlippedFaceIsInconsistentOrientation) {
  const TriangleMesh box = MakeBox(Vector3(1, 1, 1));
  auto faces = box.faces();
  std::swap(faces[0][1], faces[0][2]);
  const MeshReport r = TriangleMesh(box.vertices(), faces).Check();
  EXPECT_TRUE(r.closed());
  EXPECT_EQ(r.misoriented_edges, 3u);
  EXPECT_FALSE(r.IsSolid());
}

TEST(Mesh, DegenerateFacesAreCounted) {
  std::vector<Vector3> v = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}};
  const MeshReport r = TriangleMesh(v, {{0, 1, 2}, {0, 0, 3}, {0, 1, 3}}).Check();
  EXPECT_EQ(r.degenerate_faces, 2u);  // collinear, and a repeated index
}

TEST(Mesh, TwoComponentsAndUnreferencedVertices) {
  TriangleMesh a = MakeIcosphere(1, 1);
  TriangleMesh b = MakeIcosphere(1, 1);
  std::vector<Vector3> v = a.vertices();
  std::vector<TriangleMesh::Face> f = a.faces();
  const int offset = static_cast<int>(v.size());
  for (const Vector3& p : b.vertices()) v.push_back(p + Vector3(5, 0, 0));
  for (auto t : b.faces()) f.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  v.push_back(Vector3(100, 0, 0));  // stray vertex
  const MeshReport r = TriangleMesh(v, f).Check();
  EXPECT_EQ(r.components, 2u);
  EXPECT_EQ(r.unreferenced_vertices, 1u);
  EXPECT_EQ(r.euler_characteristic, 4);
  EXPECT_TRUE(r.IsSolid());  // two closed solids are still a solid
}

TEST(Mesh, TransformMovesEverything) {
  TriangleMesh box = MakeBox(Vector3(1, 1, 1));
  const Matrix3 R = Eigen::AngleAxisd(kPi / 2, Vector3::UnitZ()).toRotationMatrix();
  box.Transform(R, Vector3(10, 0, 0));
  const MeshReport r = box.Check();
  EXPECT_TRUE(CompareMatrices(r.bounds.min, Vector3(9.5, -0.5, -0.5), 1e-14));
  EXPECT_TRUE(CompareScalars(r.volume, 1.0, 1e-14));
}

}  // namespace
}  // namespace sulcus
