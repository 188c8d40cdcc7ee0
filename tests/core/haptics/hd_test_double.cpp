#include "tests/core/haptics/hd_test_double.h"

namespace sulcus::test::hd {

State& Get() {
  static State state;
  return state;
}

void Reset() { Get() = State{}; }

void RunServo(int n) {
  State& s = Get();
  for (int i = 0; i < n && s.callback && s.scheduler_running; ++i) {
    if (!s.servo_errors.empty()) {
      s.pending.push_back({s.servo_errors.front(), 0, 1});
      s.servo_errors.pop_front();
    }
    if (s.callback(s.user_data) == HD_CALLBACK_DONE) s.callback = nullptr;
  }
}

}  // namespace sulcus::test::hd

using sulcus::test::hd::Get;

extern "C" {

HHD hdInitDevice(HDstring name) {
  Get().calls.push_back(std::string("hdInitDevice(") + (name ? name : "default") + ")");
  if (Get().init_error != HD_SUCCESS) {
    Get().pending.push_back({Get().init_error, -7, HD_INVALID_HANDLE});
    return HD_INVALID_HANDLE;
  }
  Get().device_enabled = true;
  return 1;
}
void hdDisableDevice(HHD) {
  Get().calls.push_back("hdDisableDevice");
  Get().device_enabled = false;
}
HDErrorInfo hdGetError(void) {
  if (Get().pending.empty()) return {HD_SUCCESS, 0, 1};
  const HDErrorInfo e = Get().pending.front();
  Get().pending.pop_front();
  return e;
}
HDstring hdGetErrorString(HDErrorCode code) {
  switch (code) {
    case HD_COMM_CONFIG_ERROR:
      return "Communication configuration error";
    case HD_DEVICE_FAULT:
      return "Device fault";
    case HD_EXCEEDED_MAX_FORCE:
      return "Exceeded max force";
    default:
      return "HDAPI error";
  }
}
void hdEnable(HDenum cap) {
  Get().calls.push_back("hdEnable");
  if (cap == HD_FORCE_OUTPUT) Get().force_output = true;
}
void hdStartScheduler(void) {
  Get().calls.push_back("hdStartScheduler");
  if (Get().start_error != HD_SUCCESS) {
    Get().pending.push_back({Get().start_error, 0, 1});
    return;
  }
  Get().scheduler_running = true;
}
void hdStopScheduler(void) {
  Get().calls.push_back("hdStopScheduler");
  Get().scheduler_running = false;
}
HDSchedulerHandle hdScheduleAsynchronous(HDSchedulerCallback cb, void* data, HDushort) {
  Get().calls.push_back("hdScheduleAsynchronous");
  Get().callback = cb;
  Get().user_data = data;
  return 5;
}
void hdUnschedule(HDSchedulerHandle) {
  Get().calls.push_back("hdUnschedule");
  Get().callback = nullptr;
}
void hdBeginFrame(HHD) {
  if (Get().in_frame) ++Get().frames_unbalanced;
  Get().in_frame = true;
}
void hdEndFrame(HHD) {
  if (!Get().in_frame) ++Get().frames_unbalanced;
  Get().in_frame = false;
}
void hdGetDoublev(HDenum name, HDdouble* v) {
  if (name == HD_CURRENT_TRANSFORM)
    for (int i = 0; i < 16; ++i) v[i] = Get().transform[i];
  else if (name == HD_NOMINAL_MAX_FORCE)
    *v = Get().max_force;
}
void hdGetIntegerv(HDenum name, HDint* v) {
  if (name == HD_CURRENT_BUTTONS) *v = Get().buttons;
  if (name == HD_INPUT_DOF) *v = Get().input_dof;
  if (name == HD_OUTPUT_DOF) *v = Get().output_dof;
}
void hdSetDoublev(HDenum name, const HDdouble* v) {
  if (name == HD_CURRENT_FORCE) {
    for (int i = 0; i < 3; ++i) Get().force[i] = v[i];
    ++Get().force_writes;
  } else if (name == HD_CURRENT_TORQUE) {
    for (int i = 0; i < 3; ++i) Get().torque[i] = v[i];
    ++Get().torque_writes;
  }
}
HDstring hdGetString(HDenum name) {
  return name == HD_DEVICE_MODEL_TYPE ? "PHANToM Premium 3.0 6DOF (double)" : "";
}
}
