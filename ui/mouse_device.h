#pragma once
// The mouse and keyboard as a 6-DoF device (a UI-side backend of the device
// interface, core/haptics/device.h): the window moves a pose, the haptic thread
// reads it through a triple buffer. No force output: the force is shown, not felt.

#include <mutex>

#include "core/haptics/device.h"
#include "core/haptics/realtime.h"

namespace sulcus::ui {

class MouseKeyboardDevice final : public Device {
 public:
  explicit MouseKeyboardDevice(const RigidTransform& start);
  const DeviceCaps& caps() const override { return caps_; }
  bool Read(double t_s, DeviceSample* out) noexcept override;
  void Write(const Vector3&, const Vector3&) noexcept override {}

  // UI thread.
  /// Moves the tool by dp (mm, world) and turns it by dtheta (rad, world axes, about the
  /// tip).
  void Nudge(const Vector3& dp_W, const Vector3& dtheta_W);
  void Set(const RigidTransform& X_WH);
  const RigidTransform& pose() const { return pose_; }

 private:
  DeviceCaps caps_;
  RigidTransform pose_;  // UI thread's copy
  TripleBuffer<RigidTransform> shared_;
};

}  // namespace sulcus::ui
