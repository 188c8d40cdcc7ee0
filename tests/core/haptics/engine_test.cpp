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

RigidTransform At(double x, double y, double z) {
  return {Matrix3::Identity(), Vector3(x, y, z)};
}

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
    const bool held = d.faults.sweep + d.faults.solver > holds &&
                      d.X_WG.ToMatrix4() == before.ToMatrix4();
    held_in_a_row = held ? held_in_a_row + 1 : 0;
    most_held_in_a_row = std::max(most_held_in_a_row, held_in_a_row);
  }
  EXPECT_GT(d.faults.sweep, 0u) << "frames must be held for this test to mean anything";
  EXPECT_GE(d.faults.held, 1u);
  EXPECT_LE(most_held_in_a_row, p.max_held_frames + 1);
  for (int i = 0; i <= 140; ++i)
    Step(*model, At(1.5, 0, -3 + 0.05 * i), &d);  // out, to 4 mm above
  EXPECT_TRUE(CompareMatrices(d.X_WG.ToMatrix4(), At(1.5, 0, 4).ToMatrix4(), 1e-9));
  EXPECT_EQ(d.force_W.norm(), 0.0);
}

// A flat face dragged fast over a finely packed block meets thousands of pairs
// at the margin its move needs. With a pair budget (solve_pairs) the frame
// takes a shorter step with a smaller margin instead: it never solves with
// more than the budget (except at the margin of the shortest step it allows),
// the face still slides on, out of the block, without a fault; and once in free
// space the tool follows the device at full speed again, with no force.
struct Drag {
  int most_pairs = 0, over_budget = 0;
  std::uint64_t shortened = 0, faults = 0;
  double worst_penetration = 0, end_x = 0, free_force = 0,
         lifted_force = 0;  // at the end of the lift; after 40 frames held there
};
Drag DragAFaceOverAFineBlock(int solve_pairs) {
  test::Scene s;
  s.tool = std::make_unique<SphereTree>(test::MakeFlatFace(8, 8, 0.3, 0.2));
  s.Add(test::MakeBlock(12, 4, -1.0, -0.2, 0.2, 0.15),
        RigidTransform::Identity());  // top at z = -0.05
  EngineParams p;
  p.solve_pairs = solve_pairs;
  const auto model = s.Model(p);
  EngineData d(*model);
  ResetTool(At(-8, 0, 1), &d);
  const double lowest_cap = p.base_margin_mm + 1.25 * p.min_crowded_step_mm;
  Drag out;
  auto step = [&](const RigidTransform& X) {
    Step(*model, X, &d);
    out.most_pairs = std::max(out.most_pairs, d.num_pairs);
    if (d.num_pairs > solve_pairs && d.margin_mm > lowest_cap + 1e-12) ++out.over_budget;
    out.worst_penetration = std::max(out.worst_penetration, d.max_penetration_mm);
  };
  for (int i = 0; i <= 100; ++i)
    step(At(-8, 0, 1 - 0.015 * i));  // pressed 0.45 mm into the top
  for (int i = 1; i <= 30; ++i)
    step(At(-8 + 0.5 * i, 0, -0.5));                   // 15 mm at 0.5 mm a frame
  for (int i = 0; i < 200; ++i) step(At(7, 0, -0.5));  // held there
  out.end_x = d.X_WG.translation().x();
  for (int i = 1; i <= 40; ++i)
    step(At(7, 0, -0.5 + 0.5 * i));  // lifted, 20 mm at 0.5 mm a frame
  out.lifted_force = d.force_W.norm();
  for (int i = 0; i < 40; ++i) step(At(7, 0, 19.5));  // held up there
  out.free_force = d.force_W.norm();
  out.shortened = d.shortened_frames;
  out.faults = d.faults.total();
  return out;
}

TEST(Engine, ACrowdedPlaceShortensTheStepInsteadOfSolvingThousandsOfPairs) {
  const Drag whole = DragAFaceOverAFineBlock(0);
  const Drag budget = DragAFaceOverAFineBlock(512);
  std::printf(
      "whole set: most pairs %d; budget 512: most pairs %d, frames shortened %llu, end x "
      "%.3f, penetration %.2g, force at the lift's end %.3f N (whole set %.3f N)\n",
      whole.most_pairs, budget.most_pairs,
      static_cast<unsigned long long>(budget.shortened), budget.end_x,
      budget.worst_penetration, budget.lifted_force, whole.lifted_force);
  EXPECT_GT(whole.most_pairs, 2000)
      << "the drag must be crowded for this test to mean anything";
  EXPECT_EQ(whole.shortened, 0u);
  EXPECT_GT(budget.shortened, 0u);
  EXPECT_EQ(budget.over_budget, 0);
  EXPECT_EQ(budget.faults, 0u);
  EXPECT_EQ(whole.faults, 0u);
  EXPECT_LE(budget.worst_penetration, EngineParams{}.penetration_tolerance_mm);
  // The face reached the device's x (it slides on) in both.
  EXPECT_NEAR(budget.end_x, 7.0, 1e-6);
  EXPECT_NEAR(whole.end_x, 7.0, 1e-6);
  // Free again: the lag a slip leaves is closed at the slip's pace (a quick
  // fall, EngineParams::slip_step_mm), then no lag and no force.
  EXPECT_EQ(budget.free_force, 0.0);
  EXPECT_EQ(whole.free_force, 0.0);
}

}  // namespace
}  // namespace sulcus
