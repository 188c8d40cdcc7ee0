#include "core/haptics/engine.h"

#include <gtest/gtest.h>

#include <algorithm>
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

// A contact with more pairs than the set holds, even at the shortest step (as a
// probe laid along a finely fitted tooth): each such frame holds the rendered
// tool, and the next starts from the same pose. It must not stay held: after a
// few frames it is brought to free space next to the device, and once the hand
// pulls out the tool follows it again with no force.
TEST(Engine, AContactWithMorePairsThanTheSetHoldsNeverFreezesTheTool) {
  const test::Scene scene = ProbeOverBlock();
  // Resting on the block at the base margin, the probe meets this many pairs;
  // a set of that size holds them at rest but not at the wider margin of a
  // frame that moves the tool.
  int at_rest = 0;
  {
    const auto model = scene.Model();
    EngineData d(*model);
    ResetTool(At(0, 0, 2), &d);
    for (int i = 0; i <= 250; ++i) Step(*model, At(0, 0, 2 - 0.02 * i), &d);
    for (int i = 0; i < 5; ++i) Step(*model, At(0, 0, -3), &d);
    at_rest = d.num_pairs;
  }
  ASSERT_GT(at_rest, 0);
  EngineParams p;
  p.max_pairs = at_rest;
  const auto model = scene.Model(p);
  EngineData d(*model);
  ResetTool(At(0, 0, 2), &d);
  int held_in_a_row = 0, most_held_in_a_row = 0;
  for (int i = 0; i <= 400; ++i) {
    // Down to 3 mm inside, then dragged along the surface.
    const std::uint64_t holds = d.faults.sweep + d.faults.solver;
    const RigidTransform before = d.X_WG;
    Step(*model, i <= 250 ? At(0, 0, 2 - 0.02 * i) : At(0.01 * (i - 250), 0, -3), &d);
    // This frame held the rendered tool where it was.
    const bool held = d.faults.sweep + d.faults.solver > holds && d.X_WG.ToMatrix4() == before.ToMatrix4();
    held_in_a_row = held ? held_in_a_row + 1 : 0;
    most_held_in_a_row = std::max(most_held_in_a_row, held_in_a_row);
  }
  EXPECT_GT(d.faults.sweep, 0u) << "frames must be held for this test to mean anything";
  EXPECT_GE(d.faults.held, 1u);
  EXPECT_LE(most_held_in_a_row, p.max_held_frames + 1);
  for (int i = 0; i <= 140; ++i) Step(*model, At(1.5, 0, -3 + 0.05 * i), &d);  // out, to 4 mm above
  EXPECT_TRUE(CompareMatrices(d.X_WG.ToMatrix4(), At(1.5, 0, 4).ToMatrix4(), 1e-9));
  EXPECT_EQ(d.force_W.norm(), 0.0);
}

}  // namespace
}  // namespace sulcus
