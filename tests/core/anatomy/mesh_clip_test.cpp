// Cutting closed meshes by planes: the result is a closed solid on the keep
// side, its volume what the cut leaves, its cap flat on the plane.
#include "core/anatomy/mesh_clip.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/geometry/primitives.h"

namespace sulcus {
namespace {

TEST(MeshClip, ABoxCutInHalfIsHalfTheBoxAndClosed) {
  const TriangleMesh box = MakeBox(Vector3(4, 2, 2), 4);  // centred on the origin
  const TriangleMesh half = ClipByPlanes(box, {{Vector3(0.5, 0, 0), Vector3::UnitX()}});
  const MeshReport r = half.Check();
  EXPECT_TRUE(r.IsSolid());
  EXPECT_NEAR(r.volume, 2.5 * 2 * 2, 1e-9);
  EXPECT_NEAR(r.bounds.max.x(), 0.5, 1e-12);
  EXPECT_NEAR(r.bounds.min.x(), -2.0, 1e-12);
}

TEST(MeshClip, ASphereCutByTwoPlanesKeepsTheSliceBetweenThemWithFlatCaps) {
  const TriangleMesh sphere = MakeIcosphere(3.0, 4);
  const double full = sphere.Volume();
  // Two planes that do not meet inside it, tilted to the mesh's grid.
  const Vector3 n1 = Vector3(1, 0.2, 0.1).normalized(),
                n2 = Vector3(-1, 0.1, -0.2).normalized();
  const TriangleMesh slice = ClipByPlanes(sphere, {{1.0 * n1, n1}, {1.2 * n2, n2}});
  const MeshReport r = slice.Check();
  EXPECT_TRUE(r.IsSolid());
  EXPECT_LT(r.volume, full);
  EXPECT_GT(r.volume, 0.4 * full);
  // Every vertex on the keep side of both planes; the caps' rims on them.
  int on_plane = 0;
  for (const Vector3& v : slice.vertices()) {
    EXPECT_LE(v.dot(n1) - 1.0, 1e-9);
    EXPECT_LE(v.dot(n2) - 1.2, 1e-9);
    if (std::abs(v.dot(n1) - 1.0) < 1e-9 || std::abs(v.dot(n2) - 1.2) < 1e-9) ++on_plane;
  }
  EXPECT_GT(on_plane, 20);
  // A spherical cap's volume, taken off twice (the icosphere is a little
  // inside the sphere, so its caps are a little smaller).
  auto cap = [](double R, double d) {
    const double h = R - d;
    return std::numbers::pi * h * h * (3 * R - h) / 3;
  };
  const double expected = full - cap(3.0, 1.0) - cap(3.0, 1.2);
  EXPECT_NEAR(r.volume, expected, 0.03 * full);
}

TEST(MeshClip, ATorusCutAcrossItsHoleGetsARingShapedCap) {
  // Cut through the middle of the tube, 0.05 mm above it: the cut is an
  // annulus (a loop with a hole), and half the torus is left, plus the
  // annulus' area times 0.05.
  const TriangleMesh torus = MakeTorus(3.0, 1.0, 48, 24);
  const TriangleMesh half =
      ClipByPlanes(torus, {{Vector3(0, 0, 0.05), Vector3::UnitZ()}});
  const MeshReport r = half.Check();
  EXPECT_TRUE(r.IsSolid());
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.euler_characteristic, 0);  // still a ring
  const double annulus = std::numbers::pi * (4.0 * 4.0 - 2.0 * 2.0);
  EXPECT_NEAR(r.volume, 0.5 * torus.Volume() + 0.05 * annulus, 0.005 * torus.Volume());
  // Cut across the ring instead: two separate pieces, each a ball.
  const TriangleMesh two = ClipByPlanes(torus, {{Vector3(0.1, 0, 0), Vector3::UnitX()}});
  const MeshReport r2 = two.Check();
  EXPECT_TRUE(r2.IsSolid());
  EXPECT_EQ(r2.components, 1u);  // (the half ring is one piece)
  EXPECT_EQ(r2.euler_characteristic, 2);
}

TEST(MeshClip, APlaneThatMissesKeepsOrEmptiesTheMesh) {
  const TriangleMesh box = MakeBox(Vector3(2, 2, 2));
  EXPECT_NEAR(ClipByPlanes(box, {{Vector3(5, 0, 0), Vector3::UnitX()}}).Volume(), 8.0,
              1e-9);
  EXPECT_EQ(ClipByPlanes(box, {{Vector3(-5, 0, 0), Vector3::UnitX()}}).num_faces(), 0u);
}

TEST(MeshClip, AnOpenMeshIsRefused) {
  const TriangleMesh box = MakeBox(Vector3(2, 2, 2));
  std::vector<TriangleMesh::Face> faces = box.faces();
  faces.pop_back();
  EXPECT_THROW(ClipByPlanes(TriangleMesh(box.vertices(), faces),
                            {{Vector3::Zero(), Vector3::UnitX()}}),
               std::invalid_argument);
}

}  // namespace
}  // namespace sulcus
