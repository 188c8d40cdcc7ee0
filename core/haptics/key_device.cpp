#include "core/haptics/key_device.h"

#include <algorithm>
#include <cmath>

namespace sulcus {

MouseKeyboardDevice::MouseKeyboardDevice(const RigidTransform& start)
    : pose_(start), shared_(start) {
  caps_.name = "mouse and keyboard";
  caps_.input_dof = 6;
  caps_.output_dof = 0;
  caps_.max_force_n = 1e9;  // nothing is felt; the scene's limits shape what is shown
  caps_.max_torque_nmm = 1e9;
}

bool MouseKeyboardDevice::Read(double t_s, DeviceSample* out) noexcept {
  shared_.Acquire();
  const RigidTransform& X = shared_.front();
  axis_W_ = X.rotation().col(2);
  if (release_.exchange(false, std::memory_order_acq_rel)) offset_mm_ = 0;
  if (const double lift = lift_mm_.exchange(0, std::memory_order_acq_rel); lift > 0)
    offset_mm_ = std::max(0.0, offset_mm_ - lift);
  const double dt = last_t_ >= 0 ? std::clamp(t_s - last_t_, 0.0, 0.01) : 0.0;
  last_t_ = t_s;
  // The press: down the axis while the tissue answers with less than the hand
  // pushes, up while it answers with more (never above where the keys put it).
  const double press = press_n_.load(std::memory_order_relaxed);
  if (press > 0 || offset_mm_ > 0) {
    const double v = std::clamp(kPressGainMmSPerN * (press - answer_n_), -kPressSpeedMmS,
                                kPressSpeedMmS);
    offset_mm_ = std::max(0.0, offset_mm_ + v * dt);
    travel_mm_.store(offset_mm_, std::memory_order_relaxed);
  }
  out->X_WH = RigidTransform(X.rotation(), X.translation() - offset_mm_ * axis_W_);
  out->time_s = t_s;
  out->buttons = 0;
  return true;
}

void MouseKeyboardDevice::Write(const Vector3& force_W, const Vector3&) noexcept {
  const double f = force_W.dot(axis_W_);  // the tissue pushing back up the probe
  answer_n_ = std::isfinite(f) ? std::max(0.0, f) : 0.0;
}

void MouseKeyboardDevice::Nudge(const Vector3& dp_W, const Vector3& dtheta_W) {
  const Matrix3 R = ExpMap(dtheta_W) * pose_.rotation();
  pose_ = RigidTransform(NearestRotation(R), pose_.translation() + dp_W);
  shared_.back() = pose_;
  shared_.Publish();
}

void MouseKeyboardDevice::Set(const RigidTransform& X_WH) {
  pose_ = X_WH;
  press_n_.store(0, std::memory_order_relaxed);
  release_.store(true, std::memory_order_release);
  travel_mm_.store(0, std::memory_order_relaxed);
  shared_.back() = X_WH;
  shared_.Publish();
}

void MouseKeyboardDevice::Place(const RigidTransform& X_WH) {
  pose_ = X_WH;
  shared_.back() = X_WH;
  shared_.Publish();
}

RigidTransform MouseKeyboardDevice::tip_pose() const {
  const Vector3 z = pose_.rotation() * Vector3::UnitZ();
  return RigidTransform(pose_.rotation(), pose_.translation() - press_travel_mm() * z);
}

void MouseKeyboardDevice::PlaceTip(const RigidTransform& X_WT) {
  const Vector3 z = X_WT.rotation() * Vector3::UnitZ();
  Place(RigidTransform(X_WT.rotation(), X_WT.translation() + press_travel_mm() * z));
}

void MouseKeyboardDevice::Lift(double mm) {
  if (std::isfinite(mm) && mm > 0) lift_mm_.store(mm, std::memory_order_release);
}

void MouseKeyboardDevice::SetPress(double n) {
  press_n_.store(std::isfinite(n) ? std::clamp(n, 0.0, kPressMaxN) : 0.0,
                 std::memory_order_relaxed);
}

}  // namespace sulcus
