#pragma once
// A test double of the HDAPI functions the OpenHaptics backend calls (declared
// in core/haptics/devices/hd_api.h from the public API reference): a device
// whose stylus pose, buttons and errors the test sets, a scheduler the test
// ticks by hand, and a log of what the backend sent.

#include <deque>
#include <string>
#include <vector>

#include "core/haptics/devices/hd_api.h"

namespace sulcus::test::hd {

struct State {
  HDErrorCode init_error = HD_SUCCESS;   // hdInitDevice fails with this
  HDErrorCode start_error = HD_SUCCESS;  // hdStartScheduler fails with this
  std::deque<HDErrorCode>
      servo_errors;  // raised during the next servo ticks, one per tick
  HDdouble transform[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  HDint buttons = 0;
  HDint input_dof = 6, output_dof = 6;
  HDdouble max_force = 3.3;
  // What the backend did.
  HDdouble force[3] = {}, torque[3] = {};
  int force_writes = 0, torque_writes = 0;
  bool scheduler_running = false, device_enabled = false, force_output = false,
       in_frame = false;
  int frames_unbalanced = 0;
  std::vector<std::string> calls;
  // Internal.
  std::deque<HDErrorInfo> pending;
  HDSchedulerCallback callback = nullptr;
  void* user_data = nullptr;
};

/// The double's state, reset by Reset().
State& Get();
void Reset();
/// Runs the scheduled callback n times (as the servo thread would).
void RunServo(int n);

}  // namespace sulcus::test::hd
