#pragma once
// The mouse and keyboard as a 6-DoF device (a backend of the device interface,
// core/haptics/device.h): the window's keys and mouse, or the scripted "keys"
// student, move a pose; the haptic thread reads it through a triple buffer. No
// force output: the force is shown, not felt.
//
// The press (an admittance along the probe): the student sets the force the
// hand pushes with along the probe's axis, and on the haptic thread the hand
// moves down the axis until the tissue answers with that force (and back up
// when it answers with more), as a clinician's hand finds the floor at 0.25 N.

#include <atomic>

#include "core/haptics/device.h"
#include "core/haptics/realtime.h"

namespace sulcus {

class MouseKeyboardDevice final : public Device {
 public:
  /// How fast the press moves the hand: mm/s per newton of difference between
  /// the press and the tissue's answer (against a 2 N/mm floor, a 50 ms time
  /// constant at 1 kHz), and at most kPressSpeedMmS.
  static constexpr double kPressGainMmSPerN = 10.0;
  static constexpr double kPressSpeedMmS = 4.0;
  static constexpr double kPressMaxN = 1.0;

  explicit MouseKeyboardDevice(const RigidTransform& start);
  const DeviceCaps& caps() const override { return caps_; }
  bool Read(double t_s, DeviceSample* out) noexcept override;
  void Write(const Vector3& force_W, const Vector3&) noexcept override;

  // UI thread.
  /// Moves the tool by dp (mm, world) and turns it by dtheta (rad, world axes, about the
  /// tip).
  void Nudge(const Vector3& dp_W, const Vector3& dtheta_W);
  /// Puts the hand at X_WH; the press lets go (the hand is where it is put).
  void Set(const RigidTransform& X_WH);
  /// The hand's pose as the keys and mouse left it (without the press's travel).
  const RigidTransform& pose() const { return pose_; }
  /// Puts the hand at X_WH keeping the press and how far it has gone (a key
  /// that moves the probe along the sulcus at the floor).
  void Place(const RigidTransform& X_WH);
  /// Lifts the hand `mm` up the probe from where the press has taken it; the
  /// press brings it back down (the walking stroke's up-and-down).
  void Lift(double mm);
  /// The force the hand pushes with along the probe (N, clamped to 0..kPressMaxN).
  void SetPress(double n);
  double press() const { return press_n_.load(std::memory_order_relaxed); }
  /// How far the press has moved the hand down the probe's axis (mm).
  double press_travel_mm() const { return travel_mm_.load(std::memory_order_relaxed); }
  /// Where the keys have the tip now: the hand's pose moved down the probe by
  /// the press's travel.
  RigidTransform tip_pose() const;
  /// Places the hand so that its tip is at X_WT with the press and its travel
  /// kept (the walking keys, T).
  void PlaceTip(const RigidTransform& X_WT);

 private:
  DeviceCaps caps_;
  RigidTransform pose_;  // UI thread's copy
  TripleBuffer<RigidTransform> shared_;
  std::atomic<double> press_n_{0}, travel_mm_{0}, lift_mm_{0};
  std::atomic<bool> release_{false};
  // Haptic thread.
  double offset_mm_ = 0, last_t_ = -1, answer_n_ = 0;
  Vector3 axis_W_ = Vector3::UnitZ();
};

}  // namespace sulcus
