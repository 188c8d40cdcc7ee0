// The haptic loop's safety rules, events and commands, driven tick by tick.
#include "core/haptics/haptic_loop.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/haptics/scripted_device.h"
#include "tests/common/alloc_guard.h"
#include "tests/core/haptics/test_scenes.h"

namespace sulcus {
namespace {

using test::At;
using test::PuppetDevice;

// A probe over a block whose top is at z = 0 (object 0), and a second block far away
// (object 1).
test::Scene Blocks() {
  test::Scene s;
  s.tool = std::make_unique<SphereTree>(test::MakeProbe());
  s.Add(test::MakeBlock(3, 3, -1.5, -0.5, 0.5, 0.5), RigidTransform::Identity());
  s.Add(test::MakeBlock(3, 3, -1.5, -0.5, 0.5, 0.5), At(20, 0, 0));
  return s;
}

struct Rig {
  explicit Rig(LoopOptions options = {})
      : model(scene.Model()), loop(*model, &device, options) {}
  // One tick, keeping its events (a tick's record holds them).
  void Tick(bool overrun = false) {
    loop.Tick(overrun);
    const TickRecord& r = loop.last_record();
    events.insert(events.end(), r.events.begin(), r.events.begin() + r.num_events);
  }
  std::vector<HapticEvent> Events() { return std::exchange(events, {}); }
  std::vector<HapticEvent> events;
  test::Scene scene = Blocks();
  std::unique_ptr<EngineModel> model;
  PuppetDevice device;
  HapticLoop loop;
};

bool Has(const std::vector<HapticEvent>& events, EventKind kind, int object = -2) {
  for (const HapticEvent& e : events)
    if (e.kind == kind &&
        (object == -2 ||
         (kind == EventKind::kCommand ? e.payload.command.command : e.object) == object))
      return true;
  return false;
}

TEST(HapticLoop, RampsInLinearlyFromZeroAtStart) {
  LoopOptions options;
  options.safety.slip_n_per_s = 0;   // the ramp alone (the slip limit has its own test)
  Rig rig(options);                  // 1 kHz, ramp 0.5 s = 500 ticks
  rig.device.pose = At(0, 0, -0.5);  // pressing 0.75 mm below the rest pose: 0.75 N
  for (int i = 0; i < 700; ++i) {
    rig.Tick(false);
    const double engine = rig.loop.data().force_W.norm();
    const double expected = engine * std::min(1.0, i / 500.0);
    ASSERT_NEAR(rig.device.force.norm(), expected, 1e-12) << "tick " << i;
  }
  EXPECT_NEAR(rig.device.force.z(), 0.75, 1e-3);
}

TEST(HapticLoop, ClampsForceToTheSmallerOfSceneAndDeviceLimits) {
  Rig rig;
  rig.loop.Reset(At(0, 0, 2));
  for (int i = 0; i < 1000; ++i) {
    rig.device.pose =
        At(0, 0, 2 - 0.01 * i);  // down to 8 mm below the surface: 8 N of spring
    rig.Tick(false);
    ASSERT_LE(rig.device.force.norm(),
              2.0 + 1e-12);  // the puppet's 2 N, below the scene's 3.3 N
  }
  EXPECT_NEAR(rig.device.force.norm(), 2.0, 1e-9);
  rig.loop.Send({HapticCommand::Kind::kSetForceLimit, 0.5});
  rig.Tick(false);
  EXPECT_NEAR(rig.device.force.norm(), 0.5, 1e-9);
  rig.loop.Send({HapticCommand::Kind::kSetForceLimit, 50});  // cannot exceed the device
  rig.Tick(false);
  EXPECT_NEAR(rig.device.force.norm(), 2.0, 1e-9);
}

TEST(HapticLoop, ADeviceThatSaysItIsGoneGetsZeroForceOnThatTickAndRampsBackIn) {
  Rig rig;  // the watchdog's own timeout (10 ticks) is not waited for
  rig.device.pose = At(0, 0, -0.5);
  for (int i = 0; i < 600; ++i) rig.Tick(false);
  ASSERT_GT(rig.device.force.norm(), 0.4);
  rig.Events();
  rig.device.answering = false;
  rig.device.gone = true;
  rig.Tick(false);
  EXPECT_EQ(rig.device.force.norm(), 0.0) << "zero on the tick it is gone";
  EXPECT_TRUE(Has(rig.Events(), EventKind::kDeviceLost));
  EXPECT_EQ(rig.loop.faults().device_stalls, 1u);
  for (int i = 0; i < 30; ++i) rig.Tick(false);
  EXPECT_EQ(rig.device.force.norm(), 0.0);
  rig.device.answering = true;
  rig.device.gone = false;
  rig.Tick(false);
  EXPECT_TRUE(Has(rig.Events(), EventKind::kDeviceBack));
  EXPECT_EQ(rig.device.force.norm(), 0.0) << "the ramp restarts from zero";
  double before = 0;
  for (int i = 0; i < 100; ++i) {
    rig.Tick(false);
    EXPECT_GE(rig.device.force.norm(), before - 1e-12) << "rising, tick " << i;
    before = rig.device.force.norm();
  }
  EXPECT_GT(before, 0.0);
  EXPECT_LT(before, 0.4) << "still ramping a tenth of a second later";
}

TEST(HapticLoop, AStartDeepInsideAnObjectRampsTheForceInFromFreeSpaceWithoutAJump) {
  Rig rig;
  rig.device.pose =
      At(0.1, 0.1, -1.2);  // the tip 1.2 mm into the block's top, from the first tick
  double last = 0, worst_step = 0, most = 0;
  for (int i = 0; i < 1000; ++i) {
    rig.Tick(false);
    const double f = rig.device.force.norm();
    ASSERT_TRUE(std::isfinite(f));
    worst_step = std::max(worst_step, std::abs(f - last));
    most = std::max(most, f);
    if (i == 20) {
      EXPECT_GT(f, 0.0) << "not left without force";
    }
    last = f;
  }
  // The ramp (0.5 s to the device's 2 N: 2 N / 500 ticks) and the slip limit
  // (the force found in free space comes in at 40 N/s) bound each tick's change.
  EXPECT_LE(worst_step, 2.0 / 500 + SafetyParams{}.slip_n_per_s / 1000 + 1e-9);
  EXPECT_LE(most, 2.0 + 1e-9);
  EXPECT_GT(last, 1.0) << "the spring pulls the hand out of the block";
  EXPECT_GE(rig.loop.data().faults.inside, 1u);
  EXPECT_GT(rig.loop.data().X_WG.translation().z(), -0.01)
      << "the rendered tool is on top of the block";
}

TEST(HapticLoop, WatchdogZeroesForceWhenTheDeviceStallsAndRampsBackIn) {
  LoopOptions options;
  options.safety.device_timeout_s = 0.005;  // 5 ticks
  Rig rig(options);
  rig.device.pose = At(0, 0, -0.5);
  for (int i = 0; i < 600; ++i) rig.Tick(false);
  ASSERT_GT(rig.device.force.norm(), 0.7);
  rig.Events();
  rig.device.answering = false;
  for (int i = 0; i < 4; ++i) rig.Tick(false);
  EXPECT_GT(rig.device.force.norm(), 0.7)
      << "within the timeout the last reading is held";
  rig.Tick(false);
  EXPECT_EQ(rig.device.force.norm(), 0.0);
  EXPECT_EQ(rig.loop.faults().device_stalls, 1u);
  EXPECT_TRUE(Has(rig.Events(), EventKind::kDeviceLost));
  for (int i = 0; i < 50; ++i) rig.Tick(false);
  EXPECT_EQ(rig.device.force.norm(), 0.0);
  EXPECT_EQ(rig.loop.faults().device_stalls, 1u)
      << "one stall is one fault, however long";
  rig.device.answering = true;
  rig.Tick(false);
  EXPECT_EQ(rig.device.force.norm(), 0.0) << "the ramp restarts from zero";
  EXPECT_TRUE(Has(rig.Events(), EventKind::kDeviceBack));
  for (int i = 0; i < 250; ++i) rig.Tick(false);
  EXPECT_NEAR(rig.device.force.norm(), 0.75 * 250 / 500.0, 1e-3);
}

TEST(HapticLoop, AnOverrunTickSendsZeroAndRestartsTheRamp) {
  Rig rig;
  rig.device.pose = At(0, 0, -0.5);
  for (int i = 0; i < 600; ++i) rig.Tick(false);
  rig.Events();
  rig.Tick(true);
  EXPECT_EQ(rig.device.force.norm(), 0.0);
  EXPECT_EQ(rig.loop.faults().overruns, 1u);
  EXPECT_TRUE(Has(rig.Events(), EventKind::kOverrun));
  rig.Tick(false);
  EXPECT_NEAR(rig.device.force.norm(), 0.75 / 500.0, 1e-4);
}

TEST(HapticLoop, NanPoseIsAFaultWithZeroForceNeverANanForce) {
  Rig rig;
  rig.device.pose = At(0, 0, -0.5);
  for (int i = 0; i < 600; ++i) rig.Tick(false);
  const Vector3 held = rig.loop.data().X_WG.translation();
  // (The first tick found the tool 0.5 mm inside the block and brought it out: a fault of
  // its own.)
  const std::uint64_t faults_before = rig.loop.faults().engine;
  rig.device.pose = At(std::numeric_limits<double>::quiet_NaN(), 0, 0);
  rig.Tick(false);
  EXPECT_TRUE(rig.device.force.allFinite());
  EXPECT_EQ(rig.device.force.norm(), 0.0);
  EXPECT_EQ(rig.loop.data().X_WG.translation(), held);
  EXPECT_EQ(rig.loop.faults().engine, faults_before + 1);
  rig.device.pose = At(0, 0, -0.5);
  rig.Tick(false);
  EXPECT_LT(rig.device.force.norm(), 0.01) << "ramps back in after the fault";
}

TEST(HapticLoop, ContactEventsNameTheObject) {
  Rig rig;
  rig.loop.Reset(At(20, 0, 2));
  for (int i = 0; i < 100; ++i) {
    rig.device.pose = At(20, 0, 2 - 0.03 * i);
    rig.Tick(false);
  }
  auto events = rig.Events();
  EXPECT_TRUE(Has(events, EventKind::kContactBegan, 1));
  EXPECT_FALSE(Has(events, EventKind::kContactBegan, 0));
  HapticSnapshot s;
  ASSERT_TRUE(rig.loop.snapshots().Acquire());
  EXPECT_TRUE(rig.loop.snapshots().front().InContact(1));
  EXPECT_FALSE(rig.loop.snapshots().front().InContact(0));
  rig.device.pose = At(20, 0, 3);
  for (int i = 0; i < 10; ++i) rig.Tick(false);
  EXPECT_TRUE(Has(rig.Events(), EventKind::kContactEnded, 1));
}

TEST(HapticLoop, PauseSendsZeroAndResumeRampsIn) {
  Rig rig;
  rig.device.pose = At(0, 0, -0.5);
  for (int i = 0; i < 600; ++i) rig.Tick(false);
  rig.loop.Send({HapticCommand::Kind::kPause});
  rig.Tick(false);
  EXPECT_EQ(rig.device.force.norm(), 0.0);
  ASSERT_TRUE(rig.loop.snapshots().Acquire());
  EXPECT_TRUE(rig.loop.snapshots().front().paused);
  rig.loop.Send({HapticCommand::Kind::kResume});
  rig.Tick(false);
  EXPECT_EQ(rig.device.force.norm(), 0.0);
  rig.Tick(false);
  EXPECT_NEAR(rig.device.force.norm(), 0.75 / 500.0, 1e-4);
  const auto events = rig.Events();
  EXPECT_TRUE(
      Has(events, EventKind::kCommand, static_cast<int>(HapticCommand::Kind::kPause)));
  EXPECT_TRUE(
      Has(events, EventKind::kCommand, static_cast<int>(HapticCommand::Kind::kResume)));
}

TEST(HapticLoop, ForceEventsWithHysteresis) {
  LoopOptions options;
  options.force_event_n = 0.5;
  options.safety.ramp_s = 0;
  Rig rig(options);
  rig.device.pose = At(0, 0, -0.5);  // 0.75 N, reached within the slip limit (40 N/s)
  for (int i = 0; i < 40; ++i) rig.Tick(false);
  auto events = rig.Events();
  EXPECT_TRUE(Has(events, EventKind::kForceAbove));
  rig.device.pose = At(0, 0, 0.22);  // 0.03 N
  for (int i = 0; i < 5; ++i) rig.Tick(false);
  EXPECT_TRUE(Has(rig.Events(), EventKind::kForceBelow));
}

// Pressed 1.5 mm into the block's top near its edge, then drawn sideways off
// the edge: the rendered tool slips off within a tick or two and the engine's
// force falls by more than 0.5 N at once. The force sent falls at the slip
// limit (40 N/s beyond what the device's own move explains: no click) and is
// the engine's again within 200 ticks; a press that the device's move explains
// (straight down onto the top) is not slowed at all.
// A probe pressed 1.5 mm into a block's top, then slid sideways off its edge.
// The engine eases the slip (EngineParams::slip_step_mm): the rendered tool
// closes on the device over a few ticks, at most slip_step_mm a tick beyond the
// device's own move, round the edge. The force sent is the spring's at every
// tick (nothing held where nothing touches), falls at most k_t times that a
// tick beyond what the hand's move explains (no click), and is gone within a
// few tens of ticks (a quick fall).
TEST(HapticLoop, AToolSlippingOffAnEdgeIsFeltAsAQuickFallNotAClick) {
  LoopOptions options;
  options.safety.ramp_s = 0;
  Rig rig(options);
  const EngineParams& params = rig.model->params;
  rig.loop.Reset(At(0.5, 0, 2));
  for (int i = 0; i <= 350;
       ++i) {  // straight down to 1.5 mm below the top: every change explained
    rig.device.pose = At(0.5, 0, 2 - 0.01 * i);
    rig.Tick(false);
    EXPECT_NEAR(rig.device.force.norm(), rig.loop.data().force_W.norm(), 1e-9)
        << "tick " << i;
  }
  ASSERT_GT(rig.device.force.norm(), 1.0);
  double worst_unexplained = 0, worst_own_jump = 0, worst_held = 0;
  int last_high = -1, fall_ticks = -1;
  // The device's move as the loop saw it: its reading, on the recording grid.
  const auto seen = [&] { return rig.loop.last_record().sample.X_WH.translation(); };
  Vector3 last_force = rig.device.force, last_at = seen(),
          last_tool = rig.loop.data().X_WG.translation();
  const std::uint64_t eased_before = rig.loop.data().eased_frames;
  for (int i = 0; i < 300; ++i) {
    rig.device.pose = At(0.5 + std::min(3.0, 0.02 * i), 0,
                         -1.5);  // sideways, off the block (its edge at x = 1.5 + r)
    rig.Tick(false);
    const Vector3 f = rig.device.force, tool = rig.loop.data().X_WG.translation();
    const Vector3 spring = params.k_t * (tool - seen());
    worst_held = std::max(worst_held, f.norm() - spring.norm());
    worst_unexplained =
        std::max(worst_unexplained,
                 UnexplainedForceChange(last_force, f, last_at, seen(), params.k_t));
    worst_own_jump =
        std::max(worst_own_jump, (tool - last_tool).norm() - (seen() - last_at).norm());
    // The fall: from the last tick above 1.5 N to the first below 0.5 N (the
    // shaft then leans on the block's side, at 0.4 N).
    if (f.norm() > 1.5) {
      last_high = i;
      fall_ticks = -1;
    } else if (f.norm() < 0.5 && last_high >= 0 && fall_ticks < 0) {
      fall_ticks = i - last_high;
    }
    last_force = f;
    last_at = seen();
    last_tool = tool;
  }
  std::printf(
      "figure: 1.5 to 0.5 N in %d ticks (%llu frames eased), worst own jump "
      "%.4f mm, worst unexplained change %.4f N, force held beyond the spring "
      "%.2g N\n",
      fall_ticks,
      static_cast<unsigned long long>(rig.loop.data().eased_frames - eased_before),
      worst_own_jump, worst_unexplained, worst_held);
  EXPECT_GT(rig.loop.data().eased_frames - eased_before, 10u)
      << "the tool slips off the edge: the case this eases";
  EXPECT_LE(worst_held, 1e-9) << "the force sent is the spring's: nothing held";
  EXPECT_LE(worst_own_jump, 1.25 * params.slip_step_mm) << "the rendered tool jumped";
  EXPECT_LE(worst_unexplained, params.k_t * 1.25 * params.slip_step_mm) << "no click";
  ASSERT_GE(fall_ticks, 0) << "the force never fell";
  EXPECT_LE(fall_ticks, 60) << "a quick fall, within a few hundredths of a second";
}

TEST(HapticLoop, TickAllocatesNothing) {
  Rig rig;
  rig.loop.Reset(At(0, 0, 1));
  for (int i = 0; i < 20; ++i) {
    rig.device.pose = At(0, 0, 1 - 0.05 * i);
    rig.Tick(false);
  }
  test::AllocationGuard guard;
  for (int i = 0; i < 200; ++i) {
    rig.device.pose = At(0.01 * i, 0, -0.5);
    rig.loop.Send({HapticCommand::Kind::kSetForceScale, 0.9});
    rig.loop.Tick(i % 50 == 7);  // the loop itself, not the test's event collector
    rig.loop.snapshots().Acquire();
  }
  EXPECT_EQ(guard.allocations(), 0u);
}

TEST(Trajectory, InterpolatesAndHoldsTheEnds) {
  const Trajectory t({{0, Vector3(0, 0, 0)}, {1, Vector3(10, 0, 0)}});
  EXPECT_DOUBLE_EQ(t.Sample(0.25).X_WH.translation().x(), 2.5);
  EXPECT_DOUBLE_EQ(t.Sample(-1).X_WH.translation().x(), 0);
  EXPECT_DOUBLE_EQ(t.Sample(5).X_WH.translation().x(), 10);
  EXPECT_THROW(Trajectory({{1, Vector3::Zero()}, {1, Vector3::Zero()}}),
               std::invalid_argument);
}

TEST(Trajectory, NamedScriptsTouchTheTarget) {
  ScriptTarget target;
  target.p_W = Vector3(1, 2, 3);
  for (const std::string& name : ScriptNames()) {
    const Trajectory t = MakeScript(name, target, 4.0);
    double lowest = 1e9, farthest = 0;
    for (double s = 0; s <= 4; s += 0.001) {
      const Vector3 p = t.Sample(s).X_WH.translation() - target.p_W;
      lowest = std::min(lowest, p.z());
      farthest = std::max(farthest, p.norm());
    }
    if (name == "line") {
      EXPECT_NEAR(lowest, 4.0, 1e-9) << name;
    } else {
      EXPECT_LT(lowest, -0.29) << name << " reaches below the surface";
    }
    EXPECT_LT(farthest, 11) << name;
  }
  EXPECT_THROW(MakeScript("wiggle", target, 1), std::invalid_argument);
}

// The number of event kinds is the enum's own count: every kind below it has a
// name (and a recording reads it back), nothing at it does.
TEST(HapticLoop, EveryEventKindIsCountedAndNamed) {
  std::set<std::string> names;
  for (int k = 0; k < kNumEventKinds; ++k) {
    const std::string name = ToString(static_cast<EventKind>(k));
    EXPECT_NE(name, "?") << "kind " << k << " has no name";
    names.insert(name);
  }
  EXPECT_EQ(names.size(), static_cast<std::size_t>(kNumEventKinds)) << "names are unique";
  EXPECT_STREQ(ToString(EventKind::kCount), "?");
}

}  // namespace
}  // namespace sulcus
