#pragma once
// The OpenHaptics backend (Phantom Premium 6DOF, Geomagic/3D Systems Touch):
// HDAPI's servo loop (hdScheduleAsynchronous) reads the stylus and writes the
// latest wrench from the haptic thread; the two exchange data through triple
// buffers, so neither waits for the other. Units convert at this boundary:
// HDAPI gives millimetres in the device frame D and takes force in newtons and
// torque in mN*m (= N*mm, Sulcus's unit) about the gimbal. Non-fatal HDAPI
// errors (exceeded force or velocity, warm motors) are counted and the servo
// loop carries on; a fatal one (device fault, communication) stops the readings
// and the device reports itself lost, so the haptic loop zeroes the force on
// that tick. When the servo loop then runs error-free for kResumeFrames frames
// (the device answers again), readings resume and the loop ramps the force in.
//
// Built only when CMake finds the SDK; tests compile it against a test double.

#include <atomic>
#include <cstdint>
#include <string>

#include "core/haptics/device.h"
#include "core/haptics/realtime.h"

namespace sulcus {

struct OpenHapticsOptions {
  std::string config_name;    // empty: the default device
  RigidTransform X_WD;        // the device's base frame in the world
  RigidTransform X_ST;        // the tool (tip) frame in the stylus frame
  double max_torque_nmm = 0;  // 0: no torque output (3-DoF devices); else the limit
};

class OpenHapticsDevice final : public Device {
 public:
  explicit OpenHapticsDevice(const OpenHapticsOptions& options);
  ~OpenHapticsDevice() override;
  const DeviceCaps& caps() const override { return caps_; }
  /// Opens the device and starts the servo loop; throws DeviceError naming the
  /// HDAPI error and what to check.
  void Start() override;
  void Stop() noexcept override;
  bool Read(double t_s, DeviceSample* out) noexcept override;
  void Write(const Vector3& force_W, const Vector3& torque_W) noexcept override;
  bool lost() const noexcept override { return faulted_.load(std::memory_order_relaxed); }

  /// Error-free servo frames after a fatal error before the device counts as back.
  static constexpr int kResumeFrames = 500;

  std::uint64_t servo_ticks() const {
    return servo_ticks_.load(std::memory_order_relaxed);
  }
  std::uint64_t warnings() const {
    return warnings_.load(std::memory_order_relaxed);
  }  // non-fatal errors
  std::uint64_t fatal_errors() const { return fatal_.load(std::memory_order_relaxed); }
  std::uint32_t last_error_code() const {
    return last_error_.load(std::memory_order_relaxed);
  }

  /// The servo callback (public for the C trampoline).
  unsigned int Servo() noexcept;

 private:
  struct Reading {
    RigidTransform X_WH;
    std::uint32_t buttons = 0;
    std::uint64_t serial = 0;
  };
  struct Wrench {
    Vector3 force_D = Vector3::Zero();
    Vector3 torque_D = Vector3::Zero();  // about the gimbal (stylus origin)
  };

  OpenHapticsOptions options_;
  DeviceCaps caps_;
  unsigned int handle_ = 0;
  unsigned long schedule_ = 0;
  bool started_ = false;
  TripleBuffer<Reading> readings_;  // servo -> haptic thread
  TripleBuffer<Wrench> wrenches_;   // haptic thread -> servo
  std::uint64_t last_serial_ = 0;
  RigidTransform last_X_WS_;  // the stylus in W at the last reading (haptic thread)
  std::atomic<bool> faulted_{false};
  int clean_frames_ = 0;  // servo thread: error-free frames since the last fatal error
  std::atomic<std::uint64_t> servo_ticks_{0}, warnings_{0}, fatal_{0};
  std::atomic<std::uint32_t> last_error_{0};
};

}  // namespace sulcus
