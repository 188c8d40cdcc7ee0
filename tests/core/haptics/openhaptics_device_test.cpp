// The OpenHaptics backend against the HDAPI test double: frames, units, clamps,
// error handling, start and stop.
#include "core/haptics/devices/openhaptics_device.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <numbers>
#include <vector>

#include "core/haptics/haptic_loop.h"
#include "tests/common/compare.h"
#include "tests/core/haptics/hd_test_double.h"
#include "tests/core/haptics/test_scenes.h"

namespace sulcus {
namespace {

using test::CompareMatrices;
namespace hd = test::hd;

OpenHapticsOptions SixDof() {
  OpenHapticsOptions o;
  o.X_WD = RigidTransform(RotationFromEuler(0, 0, std::numbers::pi / 2),
                          Vector3(100, 0, 0));  // turned 90 deg about z
  o.X_ST = RigidTransform(Matrix3::Identity(),
                          Vector3(0, 0, -40));  // the tip 40 mm along -z of the stylus
  o.max_torque_nmm = 515;
  return o;
}

// Every test starts from a fresh double; `Ready` is a started device that has
// delivered its first reading.
class OpenHaptics : public ::testing::Test {
 protected:
  void SetUp() override { hd::Reset(); }
  std::unique_ptr<OpenHapticsDevice> Ready() {
    auto device = std::make_unique<OpenHapticsDevice>(SixDof());
    device->Start();
    hd::RunServo(1);
    DeviceSample s;
    EXPECT_TRUE(device->Read(0, &s));
    return device;
  }
  static Vector3 Force() {
    return {hd::Get().force[0], hd::Get().force[1], hd::Get().force[2]};
  }
  static Vector3 Torque() {
    return {hd::Get().torque[0], hd::Get().torque[1], hd::Get().torque[2]};
  }
};

TEST_F(OpenHaptics, StartsStopsAndReadsThePoseInTheWorldFrame) {
  OpenHapticsDevice device(SixDof());
  device.Start();
  EXPECT_TRUE(hd::Get().scheduler_running);
  EXPECT_TRUE(hd::Get().force_output);
  EXPECT_EQ(device.caps().name, "OpenHaptics: PHANToM Premium 3.0 6DOF (double)");
  EXPECT_EQ(device.caps().output_dof, 6);
  EXPECT_DOUBLE_EQ(device.caps().max_force_n, 3.3);

  DeviceSample s;
  EXPECT_FALSE(device.Read(0, &s)) << "no servo tick yet: no reading";
  // Stylus at (10, 20, 30) mm in the device frame, not rotated.
  hd::Get().transform[12] = 10;
  hd::Get().transform[13] = 20;
  hd::Get().transform[14] = 30;
  hd::Get().buttons = 1;
  hd::RunServo(1);
  ASSERT_TRUE(device.Read(0.001, &s));
  // W = Rz(90) * (p_S + (0, 0, -40)) + (100, 0, 0): (10, 20, -10) -> (-20, 10, -10) +
  // (100, 0, 0).
  EXPECT_TRUE(CompareMatrices(s.X_WH.translation(), Vector3(80, 10, -10), 1e-12));
  EXPECT_EQ(s.buttons, 1u);
  EXPECT_FALSE(device.Read(0.002, &s)) << "the same reading again is not fresh";

  device.Stop();
  EXPECT_FALSE(hd::Get().scheduler_running);
  EXPECT_FALSE(hd::Get().device_enabled);
  const std::vector<std::string> expected = {"hdInitDevice(default)",  "hdEnable",
                                             "hdScheduleAsynchronous", "hdStartScheduler",
                                             "hdStopScheduler",        "hdUnschedule",
                                             "hdDisableDevice"};
  EXPECT_EQ(hd::Get().calls, expected);
  EXPECT_EQ(hd::Get().frames_unbalanced, 0);
}

TEST_F(OpenHaptics, ForceAndTorqueGoOutInTheDeviceFrameAboutTheGimbal) {
  auto ready = Ready();
  OpenHapticsDevice& device = *ready;
  // 1 N along world +x at the tip, no torque about the tip.
  device.Write(Vector3(1, 0, 0), Vector3::Zero());
  hd::RunServo(1);
  // In D (turned +90 about z): world +x is device -y.
  EXPECT_TRUE(CompareMatrices(Force(), Vector3(0, -1, 0), 1e-12));
  // Lever arm from gimbal to tip: (0, 0, -40) mm; torque = r x F = (0, -40, 0) N*mm in W,
  // which is (-40, 0, 0) in D; N*mm is mN*m, the unit HDAPI takes.
  EXPECT_TRUE(CompareMatrices(Torque(), Vector3(-40, 0, 0), 1e-12));
}

TEST_F(OpenHaptics, ClampsAtTheBoundaryAndZeroesNan) {
  auto ready = Ready();
  OpenHapticsDevice& device = *ready;
  device.Write(Vector3(0, 0, 50), Vector3(0, 0, 5000));
  hd::RunServo(1);
  EXPECT_NEAR(Force().norm(), 3.3, 1e-12);
  EXPECT_NEAR(Torque().norm(), 515, 1e-9);
  device.Write(Vector3(0, 0, std::numeric_limits<double>::quiet_NaN()), Vector3::Zero());
  hd::RunServo(1);
  EXPECT_EQ(hd::Get().force[2], 0.0);
}

TEST_F(OpenHaptics, NonFatalErrorsAreCountedAndTheLoopGoesOn) {
  OpenHapticsDevice device(SixDof());
  device.Start();
  hd::Get().servo_errors = {HD_EXCEEDED_MAX_FORCE, HD_WARM_MOTORS};
  hd::RunServo(3);
  EXPECT_EQ(device.warnings(), 2u);
  EXPECT_EQ(device.fatal_errors(), 0u);
  DeviceSample s;
  EXPECT_TRUE(device.Read(0, &s));
}

TEST_F(OpenHaptics, AFatalErrorStopsReadingsAndForces) {
  auto ready = Ready();
  OpenHapticsDevice& device = *ready;
  DeviceSample s;
  device.Write(Vector3(0, 0, 1), Vector3::Zero());
  hd::Get().servo_errors = {HD_DEVICE_FAULT};
  hd::RunServo(1);
  EXPECT_EQ(device.fatal_errors(), 1u);
  EXPECT_EQ(device.last_error_code(), HD_DEVICE_FAULT);
  EXPECT_FALSE(device.Read(0.001, &s)) << "the loop's watchdog takes over";
  hd::RunServo(1);
  EXPECT_EQ(hd::Get().force[2], 0.0) << "no force once faulted";
}

TEST_F(OpenHaptics, AFaultedDeviceIsLostAndComesBackAfterARunOfCleanFrames) {
  auto ready = Ready();
  OpenHapticsDevice& device = *ready;
  EXPECT_FALSE(device.lost());
  hd::Get().servo_errors = {HD_COMM_ERROR};
  hd::RunServo(1);
  EXPECT_TRUE(device.lost());
  DeviceSample s;
  hd::RunServo(OpenHapticsDevice::kResumeFrames - 1);
  EXPECT_TRUE(device.lost()) << "not back before a run of clean frames";
  EXPECT_FALSE(device.Read(0.1, &s));
  hd::Get().servo_errors = {HD_COMM_ERROR};  // a flicker starts the count again
  hd::RunServo(1);
  hd::RunServo(OpenHapticsDevice::kResumeFrames - 1);
  EXPECT_TRUE(device.lost());
  hd::RunServo(1);
  EXPECT_FALSE(device.lost());
  EXPECT_TRUE(device.Read(0.2, &s)) << "readings again";
  EXPECT_EQ(device.fatal_errors(), 2u);
}

// The haptic loop over the double: a probe pressed into a block; the device
// faults mid-contact: zero force on the loop's next tick (not after the
// watchdog's timeout), the loss and the return as events, the force ramped in.
TEST_F(OpenHaptics, TheLoopZeroesForceOnTheTickTheDeviceFaultsAndRampsInWhenItIsBack) {
  test::Scene scene;
  scene.tool = std::make_unique<SphereTree>(test::MakeProbe());
  scene.Add(test::MakeBlock(3, 3, -1.5, -0.5, 0.5, 0.5), RigidTransform::Identity());
  auto model = scene.Model();
  OpenHapticsOptions o;
  o.max_torque_nmm = 515;  // device frame = world, tool frame = stylus
  OpenHapticsDevice device(o);
  device.Start();
  HapticLoop loop(*model, &device, {});
  std::vector<EventKind> events;
  auto tick = [&] {
    hd::RunServo(1);
    loop.Tick(false);
    const TickRecord& r = loop.last_record();
    for (int i = 0; i < r.num_events; ++i) events.push_back(r.events[i].kind);
    return Force().norm();
  };
  auto seen = [&](EventKind k) {
    return std::find(events.begin(), events.end(), k) != events.end();
  };
  hd::Get().transform[14] = 3;  // above the block
  for (int i = 0; i < 50; ++i) tick();
  hd::Get().transform[14] = -0.5;  // pressed 0.5 mm into its top
  for (int i = 0; i < 800; ++i) tick();
  ASSERT_GT(Force().norm(), 0.3);
  ASSERT_FALSE(seen(EventKind::kDeviceLost));

  hd::Get().servo_errors = {HD_DEVICE_FAULT};
  hd::RunServo(1);  // the error is known at the end of the servo frame
  loop.Tick(false);
  const TickRecord& lost = loop.last_record();
  EXPECT_EQ(lost.force_W.norm(), 0.0) << "the loop's output is zero on its next tick";
  hd::RunServo(1);
  EXPECT_EQ(Force().norm(), 0.0) << "and the next servo frame sends nothing";
  ASSERT_GE(lost.num_events, 1);
  EXPECT_TRUE(
      std::any_of(lost.events.begin(), lost.events.begin() + lost.num_events,
                  [](const HapticEvent& e) { return e.kind == EventKind::kDeviceLost; }));
  for (int i = 0; i < OpenHapticsDevice::kResumeFrames - 3; ++i) EXPECT_EQ(tick(), 0.0);
  EXPECT_FALSE(seen(EventKind::kDeviceBack));
  for (int i = 0; i < 5; ++i) tick();
  EXPECT_TRUE(seen(EventKind::kDeviceBack));
  double f = 0;
  for (int i = 0; i < 100; ++i) f = tick();
  EXPECT_GT(f, 0.0);
  EXPECT_LT(f, 0.3) << "ramping in, not a jump back to full force";
  for (int i = 0; i < 600; ++i) f = tick();
  EXPECT_GT(f, 0.3) << "and back to full force";
  device.Stop();
}

TEST_F(OpenHaptics, OpenFailureSaysWhatToCheck) {
  hd::Get().init_error = HD_COMM_CONFIG_ERROR;
  OpenHapticsDevice device(SixDof());
  try {
    device.Start();
    FAIL();
  } catch (const DeviceError& e) {
    EXPECT_EQ(std::string(e.what()),
              "OpenHaptics: cannot open the default device: Communication configuration "
              "error (HDAPI error 0x0700, "
              "internal -7). Is the device plugged in, its driver running and the device "
              "calibrated? "
              "(`sulcus-cli devices` lists what is plugged in.)");
  }
  EXPECT_FALSE(hd::Get().scheduler_running);
}

TEST_F(OpenHaptics, SchedulerFailureCleansUp) {
  hd::Get().start_error = HD_TIMER_ERROR;
  OpenHapticsDevice device(SixDof());
  EXPECT_THROW(device.Start(), DeviceError);
  EXPECT_FALSE(hd::Get().device_enabled);
  EXPECT_EQ(hd::Get().callback, nullptr);
}

TEST_F(OpenHaptics, ThreeDofDeviceGetsNoTorque) {
  hd::Get().output_dof = 3;
  OpenHapticsDevice device(SixDof());
  device.Start();
  EXPECT_EQ(device.caps().output_dof, 3);
  hd::RunServo(1);
  DeviceSample s;
  device.Read(0, &s);
  device.Write(Vector3(1, 0, 0), Vector3(0, 0, 10));
  hd::RunServo(1);
  EXPECT_EQ(hd::Get().torque_writes, 0);
  EXPECT_EQ(hd::Get().force_writes, 2);
}

}  // namespace
}  // namespace sulcus
