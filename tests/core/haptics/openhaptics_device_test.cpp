// The OpenHaptics backend against the HDAPI test double: frames, units, clamps,
// error handling, start and stop.
#include "core/haptics/devices/openhaptics_device.h"

#include <gtest/gtest.h>

#include <memory>
#include <numbers>

#include "tests/common/compare.h"
#include "tests/core/haptics/hd_test_double.h"

namespace sulcus {
namespace {

using test::CompareMatrices;
namespace hd = test::hd;

OpenHapticsOptions SixDof() {
  OpenHapticsOptions o;
  o.X_WD = RigidTransform(RotationFromEuler(0, 0, std::numbers::pi / 2), Vector3(100, 0, 0));  // turned 90 deg about z
  o.X_ST = RigidTransform(Matrix3::Identity(), Vector3(0, 0, -40));  // the tip 40 mm along -z of the stylus
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
  static Vector3 Force() { return {hd::Get().force[0], hd::Get().force[1], hd::Get().force[2]}; }
  static Vector3 Torque() { return {hd::Get().torque[0], hd::Get().torque[1], hd::Get().torque[2]}; }
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
  // W = Rz(90) * (p_S + (0, 0, -40)) + (100, 0, 0): (10, 20, -10) -> (-20, 10, -10) + (100, 0, 0).
  EXPECT_TRUE(CompareMatrices(s.X_WH.translation(), Vector3(80, 10, -10), 1e-12));
  EXPECT_EQ(s.buttons, 1u);
  EXPECT_FALSE(device.Read(0.002, &s)) << "the same reading again is not fresh";

  device.Stop();
  EXPECT_FALSE(hd::Get().scheduler_running);
  EXPECT_FALSE(hd::Get().device_enabled);
  const std::vector<std::string> expected = {"hdInitDevice(default)", "hdEnable", "hdScheduleAsynchronous",
                                             "hdStartScheduler", "hdStopScheduler", "hdUnschedule",
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

TEST_F(OpenHaptics, OpenFailureSaysWhatToCheck) {
  hd::Get().init_error = HD_COMM_CONFIG_ERROR;
  OpenHapticsDevice device(SixDof());
  try {
    device.Start();
    FAIL();
  } catch (const DeviceError& e) {
    EXPECT_EQ(std::string(e.what()),
              "OpenHaptics: cannot open the default device: Communication configuration error (HDAPI error 0x0700, "
              "internal -7). Is the device plugged in, its driver running and the device calibrated? "
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
