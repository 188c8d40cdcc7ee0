#include "core/haptics/engine.h"

#include <gtest/gtest.h>

#include <limits>

#include "tests/common/alloc_guard.h"
#include "tests/common/compare.h"
#include "tests/core/haptics/test_scenes.h"

namespace sulcus {
namespace {

using test::CompareMatrices;

// A probe over a block whose top sphere apexes are at z = 0.
test::Scene ProbeOverBlock() {
  test::Scene s;
  s.tool = std::make_unique<SphereTree>(test::MakeProbe());
  s.Add(test::MakeBlock(3, 3, -1.5, -0.5, 0.5, 0.5), RigidTransform::Identity());
  return s;
}

RigidTransform At(double x, double y, double z) { return {Matrix3::Identity(), Vector3(x, y, z)}; }

TEST(Engine, FreeMotionFollowsTheDeviceWithZeroForce) {
  const test::Scene scene = ProbeOverBlock();
  const auto model = scene.Model();
  EngineData d(*model);
  for (int i = 0; i < 50; ++i) {
    const RigidTransform X = At(0.01 * i, 0, 5 + 0.02 * i);
    Step(*model, X, &d);
    EXPECT_TRUE(CompareMatrices(d.X_WG.ToMatrix4(), X.ToMatrix4(), 1e-12));
    EXPECT_EQ(d.force_W.norm(), 0.0);
    EXPECT_EQ(d.num_pairs, 0);
  }
}

TEST(Engine, PushOnTheBlockRestsOnItsSurfaceWithTheSpringForce) {
  const test::Scene scene = ProbeOverBlock();
  const auto model = scene.Model();
  EngineData d(*model);
  ResetTool(At(0, 0, 2), &d);
  for (int i = 0; i <= 200; ++i) Step(*model, At(0, 0, 2 - 0.02 * i), &d);  // to z = -2
  // The tip (r 0.25) rests on the sphere apex at z = 0: tip centre at 0.25.
  EXPECT_NEAR(d.X_WG.translation().z(), 0.25, 1e-4);
  EXPECT_NEAR(d.force_W.z(), 1.0 * (0.25 - (-2.0)), 1e-4);
  EXPECT_LT(d.max_penetration_mm, 1e-4);
  EXPECT_EQ(d.qp_status, QpStatus::kSolved);
  EXPECT_GT(d.active_contacts, 0);
  EXPECT_EQ(d.faults.total(), 0u);
}

TEST(Engine, StepAllocatesNothing) {
  const test::Scene scene = ProbeOverBlock();
  const auto model = scene.Model();
  EngineData d(*model);
  ResetTool(At(0, 0, 1), &d);
  for (int i = 0; i < 50; ++i) Step(*model, At(0, 0, 1 - 0.03 * i), &d);
  test::AllocationGuard guard;
  for (int i = 0; i < 200; ++i) Step(*model, At(0.01 * i, 0, -0.5), &d);
  EXPECT_EQ(guard.allocations(), 0u);
  EXPECT_GT(d.num_pairs, 0);
}

TEST(Engine, NonFiniteDevicePoseIsAFaultWithZeroForce) {
  const test::Scene scene = ProbeOverBlock();
  const auto model = scene.Model();
  EngineData d(*model);
  ResetTool(At(0, 0, 1), &d);
  Step(*model, At(0, 0, -0.5), &d);
  const RigidTransform held = d.X_WG;
  Step(*model, At(std::numeric_limits<double>::quiet_NaN(), 0, 0), &d);
  EXPECT_EQ(d.faults.nonfinite_device, 1u);
  EXPECT_EQ(d.force_W.norm(), 0.0);
  EXPECT_TRUE(CompareMatrices(d.X_WG.ToMatrix4(), held.ToMatrix4(), 0.0));
}

TEST(Engine, ForceAndTorqueSaturateAtTheDeviceLimits) {
  const test::Scene scene = ProbeOverBlock();
  EngineParams p;
  p.max_force_n = 1.0;
  const auto model = scene.Model(p);
  EngineData d(*model);
  ResetTool(At(0, 0, 1), &d);
  for (int i = 0; i <= 100; ++i) Step(*model, At(0, 0, 1 - 0.05 * i), &d);  // 4 mm inside
  EXPECT_NEAR(d.force_W.norm(), 1.0, 1e-12);
  EXPECT_TRUE(d.force_saturated);
  EXPECT_GT(d.force_W.z(), 0);  // still pointing out of the block
}

TEST(Engine, TimingsAreReported) {
  const test::Scene scene = ProbeOverBlock();
  const auto model = scene.Model();
  EngineData d(*model);
  ResetTool(At(0, 0, 1), &d);
  Step(*model, At(0, 0, -0.2), &d);
  EXPECT_GE(d.timings.collide_us, 0);
  EXPECT_GE(d.timings.solve_us, 0);
  EXPECT_GE(d.timings.total_us, d.timings.collide_us);
  EXPECT_GE(d.linearizations, 1);
}

}  // namespace
}  // namespace sulcus
