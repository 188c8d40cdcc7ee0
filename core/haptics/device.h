#pragma once
// The device layer's one interface (docs/architecture.md, "One haptic frame" and
// "A run: the Session"): pose, buttons and a time stamp in; force and torque out; what
// the device can do. Backends: scripted trajectories and replays (here), OpenHaptics
// (devices/), the mouse and keyboard (in the window, ui/). Units at this interface are
// Sulcus's: millimetres, newtons, newton-millimetres, the world frame W; a driver
// converts at its own boundary.

#include <cstdint>
#include <stdexcept>
#include <string>

#include "core/geometry/transform.h"
#include "core/haptics/pose_grid.h"

namespace sulcus {

/// One reading of a device.
struct DeviceSample {
  RigidTransform X_WH;        // the device ("haptic") tool in the world
  std::uint32_t buttons = 0;  // bit i: button i pressed
  double time_s = 0;          // the device's own time stamp
  // The loop snaps X_WH to the recording grid (pose_grid.h) and keeps its code
  // here. A replay hands the loop readings already on the grid (`coded`), or, from
  // a recording of format 2, readings to use exactly as given (`as_given`).
  PoseCode code;
  bool coded = false;
  bool as_given = false;
};

struct DeviceCaps {
  std::string name;
  int input_dof = 6;   // 3: position only (orientation fixed)
  int output_dof = 0;  // 0: no force feedback; 3: force; 6: force and torque
  double max_force_n = 0;
  double max_torque_nmm = 0;
  Vector3 workspace_min_W = Vector3::Constant(-1e9);
  Vector3 workspace_max_W = Vector3::Constant(1e9);
};

/// Thrown by Start() (never on the haptic thread).
class DeviceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Device {
 public:
  virtual ~Device() = default;
  virtual const DeviceCaps& caps() const = 0;

  /// Opens the device; throws DeviceError with what went wrong and what to do.
  virtual void Start() {}
  virtual void Stop() noexcept {}

  /// Haptic thread: the reading for loop time t_s (seconds since the loop
  /// started). False when the device gave no fresh reading (it stalled or is
  /// gone); the loop's watchdog then decides. Never allocates, never throws.
  virtual bool Read(double t_s, DeviceSample* out) noexcept = 0;

  /// Haptic thread: the force and torque to render, already clamped by the loop.
  virtual void Write(const Vector3& force_W, const Vector3& torque_W) noexcept = 0;

  /// True once a scripted or replayed input has no more frames.
  virtual bool finished() const noexcept { return false; }

  /// Haptic thread: true while the device knows it is gone (a fatal driver
  /// error, unplugged), so that the loop zeroes the force on this tick rather
  /// than after its watchdog's timeout. A device that cannot tell returns false
  /// and the watchdog decides from stale readings.
  virtual bool lost() const noexcept { return false; }
};

}  // namespace sulcus
