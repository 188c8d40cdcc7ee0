#include "core/spheretree/metrics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/geometry/primitives.h"

namespace sulcus {
namespace {

SphereTree OneSphere(const Vector3& c, double r) {
  SphereTree t;
  t.levels = 1;
  t.AddNode(c, r, 0);
  return t;
}

TEST(Metrics, SingleSphereAroundASphereHasKnownFigures) {
  const TriangleMesh ball = MakeIcosphere(5, 5);  // facets within 0.006 mm of r = 5
  const TreeMetrics m = EvaluateSphereTree(ball, OneSphere(Vector3::Zero(), 6));
  const LevelMetrics& l = m.leaves();
  EXPECT_NEAR(l.protrusion_max_mm, 1.0, 0.01);
  EXPECT_NEAR(l.protrusion_mean_mm, 1.0, 0.01);
  EXPECT_EQ(l.coverage, 1.0);
  // (6^3 - 5^3) / 5^3 = 0.728; Monte Carlo with 768 points: within 0.1 (3 sigma).
  EXPECT_NEAR(l.excess_volume, 0.728, 0.1);
  EXPECT_NEAR(m.largest_extent_mm, 10.0, 1e-9);
}

TEST(Metrics, HalfCoveredAndInsideSpheres) {
  const TriangleMesh ball = MakeIcosphere(5, 5);
  // A sphere inside the solid: no protrusion, covers nothing.
  const TreeMetrics inner = EvaluateSphereTree(ball, OneSphere(Vector3::Zero(), 2));
  EXPECT_EQ(inner.leaves().protrusion_max_mm, 0.0);
  EXPECT_EQ(inner.leaves().coverage, 0.0);
  EXPECT_EQ(inner.leaves().excess_volume, 0.0);
  // A big sphere holding the upper half (z > 0) of the surface: coverage ~ 1/2.
  const TreeMetrics half = EvaluateSphereTree(ball, OneSphere(Vector3(0, 0, 100), 100));
  EXPECT_NEAR(half.leaves().coverage, 0.5, 0.02);
}

TEST(Metrics, ChildOutsideItsParentIsCounted) {
  SphereTree t;
  t.levels = 2;
  t.AddNode(Vector3::Zero(), 6, 0);
  t.AddNode(Vector3(2, 0, 0), 3, 1);   // inside: 2 + 3 <= 6
  t.AddNode(Vector3(-4, 0, 0), 3, 1);  // sticks out: 4 + 3 > 6
  t.first_child[0] = 1;
  t.child_count[0] = 2;
  const TreeMetrics m = EvaluateSphereTree(MakeIcosphere(5, 3), t);
  EXPECT_DOUBLE_EQ(m.levels[0].children_inside, 1.0);  // the root has no parent
  EXPECT_DOUBLE_EQ(m.levels[1].children_inside, 0.5);
}

}  // namespace
}  // namespace sulcus
