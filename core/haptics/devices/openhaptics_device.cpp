#include "core/haptics/devices/openhaptics_device.h"

#include <algorithm>
#include <cstdio>

#include "core/haptics/devices/hd_api.h"

namespace sulcus {
namespace {

HDCallbackCode HDCALLBACK ServoTrampoline(void* self) {
  return static_cast<OpenHapticsDevice*>(self)->Servo();
}

bool IsNonFatal(HDErrorCode code) {
  return code == HD_EXCEEDED_MAX_FORCE || code == HD_EXCEEDED_MAX_FORCE_IMPULSE ||
         code == HD_EXCEEDED_MAX_VELOCITY || code == HD_WARM_MOTORS ||
         code == HD_FORCE_ERROR;
}

std::string Describe(const HDErrorInfo& e) {
  char code[64];
  std::snprintf(code, sizeof code, " (HDAPI error 0x%04x, internal %d)", e.errorCode,
                e.internalErrorCode);
  const char* text = hdGetErrorString(e.errorCode);
  return std::string(text ? text : "unknown error") + code;
}

// Drains HDAPI's error stack; returns the first error, or success.
HDErrorInfo FirstError() {
  HDErrorInfo first = hdGetError();
  for (int i = 0; i < 8 && first.errorCode != HD_SUCCESS; ++i)
    if (hdGetError().errorCode == HD_SUCCESS) break;
  return first;
}

}  // namespace

OpenHapticsDevice::OpenHapticsDevice(const OpenHapticsOptions& options)
    : options_(options) {
  caps_.name = "OpenHaptics";
}

OpenHapticsDevice::~OpenHapticsDevice() { Stop(); }

void OpenHapticsDevice::Start() {
  if (started_) return;
  const char* config =
      options_.config_name.empty() ? HD_DEFAULT_DEVICE : options_.config_name.c_str();
  handle_ = hdInitDevice(config);
  const std::string which = options_.config_name.empty()
                                ? "the default device"
                                : "'" + options_.config_name + "'";
  if (const HDErrorInfo e = FirstError(); e.errorCode != HD_SUCCESS)
    throw DeviceError(
        "OpenHaptics: cannot open " + which + ": " + Describe(e) +
        ". Is the device plugged in, its driver running and the device calibrated? "
        "(`sulcus-cli devices` lists what is plugged in.)");
  const char* model = hdGetString(HD_DEVICE_MODEL_TYPE);
  caps_.name = std::string("OpenHaptics: ") + (model ? model : "unknown model");
  HDint input_dof = 6, output_dof = 3;
  hdGetIntegerv(HD_INPUT_DOF, &input_dof);
  hdGetIntegerv(HD_OUTPUT_DOF, &output_dof);
  HDdouble max_force = 0;
  hdGetDoublev(HD_NOMINAL_MAX_FORCE, &max_force);
  caps_.input_dof = input_dof;
  caps_.output_dof =
      options_.max_torque_nmm > 0 && output_dof >= 6 ? 6 : std::min(output_dof, 3);
  caps_.max_force_n = max_force > 0 ? max_force : 0;
  caps_.max_torque_nmm = caps_.output_dof == 6 ? options_.max_torque_nmm : 0;
  hdEnable(HD_FORCE_OUTPUT);
  schedule_ = hdScheduleAsynchronous(ServoTrampoline, this, HD_MAX_SCHEDULER_PRIORITY);
  hdStartScheduler();
  if (const HDErrorInfo e = FirstError(); e.errorCode != HD_SUCCESS) {
    hdUnschedule(schedule_);
    hdDisableDevice(handle_);
    throw DeviceError("OpenHaptics: cannot start the servo loop for " + which + ": " +
                      Describe(e));
  }
  started_ = true;
}

void OpenHapticsDevice::Stop() noexcept {
  if (!started_) return;
  started_ = false;
  hdStopScheduler();
  hdUnschedule(schedule_);
  hdDisableDevice(handle_);
}

unsigned int OpenHapticsDevice::Servo() noexcept {
  hdBeginFrame(handle_);
  HDdouble m[16] = {};
  HDint buttons = 0;
  hdGetDoublev(HD_CURRENT_TRANSFORM, m);
  hdGetIntegerv(HD_CURRENT_BUTTONS, &buttons);
  wrenches_.Acquire();
  Wrench w = wrenches_.front();
  const bool faulted = faulted_.load(std::memory_order_relaxed);
  // The boundary's own clamp: never more than the device's nominal force.
  if (faulted || !w.force_D.allFinite() || !w.torque_D.allFinite()) w = Wrench{};
  if (w.force_D.norm() > caps_.max_force_n)
    w.force_D *= caps_.max_force_n / w.force_D.norm();
  if (w.torque_D.norm() > caps_.max_torque_nmm)
    w.torque_D *= caps_.max_torque_nmm / std::max(w.torque_D.norm(), 1e-300);
  const HDdouble force[3] = {w.force_D.x(), w.force_D.y(), w.force_D.z()};
  hdSetDoublev(HD_CURRENT_FORCE, force);
  if (caps_.output_dof == 6) {
    const HDdouble torque[3] = {w.torque_D.x(), w.torque_D.y(),
                                w.torque_D.z()};  // N*mm = mN*m
    hdSetDoublev(HD_CURRENT_TORQUE, torque);
  }
  hdEndFrame(handle_);
  servo_ticks_.fetch_add(1, std::memory_order_relaxed);

  bool fatal = false;
  for (int i = 0; i < 8; ++i) {
    const HDErrorInfo e = hdGetError();
    if (e.errorCode == HD_SUCCESS) break;
    last_error_.store(e.errorCode, std::memory_order_relaxed);
    if (IsNonFatal(e.errorCode)) {
      warnings_.fetch_add(1, std::memory_order_relaxed);
    } else {
      fatal = true;
    }
  }
  if (fatal) {
    fatal_.fetch_add(1, std::memory_order_relaxed);
    faulted_.store(true, std::memory_order_relaxed);
    clean_frames_ = 0;
  }
  if (faulted_.load(std::memory_order_relaxed)) {
    // No readings while lost; back after a run of error-free frames.
    if (fatal || ++clean_frames_ < kResumeFrames) return HD_CALLBACK_CONTINUE;
    faulted_.store(false, std::memory_order_relaxed);
  }

  // Column-major 4x4, millimetres, stylus frame S in the device frame D.
  Matrix3 R;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) R(r, c) = m[c * 4 + r];
  const RigidTransform X_DS(R, Vector3(m[12], m[13], m[14]));
  Reading& out = readings_.back();
  out.X_WH = options_.X_WD * X_DS * options_.X_ST;
  out.buttons = static_cast<std::uint32_t>(buttons);
  ++out.serial;
  const std::uint64_t serial = out.serial;
  readings_.Publish();
  readings_.back().serial = serial;  // the next slot continues the count
  return HD_CALLBACK_CONTINUE;
}

bool OpenHapticsDevice::Read(double t_s, DeviceSample* out) noexcept {
  if (faulted_.load(std::memory_order_relaxed)) return false;
  readings_.Acquire();
  const Reading& r = readings_.front();
  if (r.serial == 0) return false;
  out->X_WH = r.X_WH;
  out->buttons = r.buttons;
  out->time_s = t_s;
  last_X_WS_ = r.X_WH * options_.X_ST.inverse();
  const bool fresh = r.serial != last_serial_;
  last_serial_ = r.serial;
  return fresh;
}

void OpenHapticsDevice::Write(const Vector3& force_W, const Vector3& torque_W) noexcept {
  // The engine's torque is about the tool origin (the tip); the device's about
  // the gimbal (the stylus origin S): T_S = T_tip + (p_tip - p_S) x F.
  const Vector3 p_tip = last_X_WS_ * options_.X_ST.translation();
  const Vector3 torque_S_W = torque_W + (p_tip - last_X_WS_.translation()).cross(force_W);
  const Matrix3 R_DW = options_.X_WD.rotation().transpose();
  Wrench& w = wrenches_.back();
  w.force_D = R_DW * force_W;
  w.torque_D = R_DW * torque_S_W;
  wrenches_.Publish();
}

}  // namespace sulcus
