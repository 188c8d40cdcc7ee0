#include "ui/mouse_device.h"

namespace sulcus::ui {

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
  out->X_WH = shared_.front();
  out->time_s = t_s;
  out->buttons = 0;
  return true;
}

void MouseKeyboardDevice::Nudge(const Vector3& dp_W, const Vector3& dtheta_W) {
  const Matrix3 R = ExpMap(dtheta_W) * pose_.rotation();
  Set(RigidTransform(NearestRotation(R), pose_.translation() + dp_W));
}

void MouseKeyboardDevice::Set(const RigidTransform& X_WH) {
  pose_ = X_WH;
  shared_.back() = X_WH;
  shared_.Publish();
}

}  // namespace sulcus::ui
