#pragma once
// The haptic thread: runs HapticLoop::Tick at a fixed rate with absolute
// deadlines (clock_nanosleep, TIMER_ABSTIME), asks for real-time priority and a
// pinned core and carries on without them (saying so once), keeps timing
// statistics without allocating, and hands every tick's record to a sink when
// one is attached. Everything another thread reads is atomic or lock-free.

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

#include "core/haptics/haptic_loop.h"
#include "core/haptics/realtime.h"

namespace sulcus {

struct ThreadOptions {
  bool realtime = true;      // ask for SCHED_FIFO and a pinned core
  int cpu = -1;              // the core to pin to; -1: the last one
  bool free_run = false;     // no sleeping: as fast as possible (replays)
  double stall_periods = 3;  // a tick this many periods late trips the watchdog
  // The last part of each wait is spent polling the clock instead of sleeping,
  // so that the tick starts on time rather than when the kernel wakes the
  // thread (on a virtual machine 20 to 40 us late, and in one wake of a hundred
  // later than 60 us: at 10 kHz, a missed deadline). Microseconds; negative:
  // the default, 90 % of the period and at most 100 us; 0: sleep the whole wait.
  // Whatever the spin, the thread sleeps at least a tenth of each period after
  // its work (PollFrom), so that a real-time thread leaves its core's other
  // work room and the kernel never throttles it.
  double spin_us = -1;
  std::uint64_t max_ticks = 0;  // stop after this many ticks (0: until Stop())
  bool stop_when_device_finished = true;
  TickSink* sink =
      nullptr;  // gets every tick's record (a Session, a RecordingWriter); not owned
};

/// Timing statistics, written by the haptic thread, readable any time.
struct TimingStats {
  TimeHistogram period_us;  // between successive tick starts
  TimeHistogram step_us;    // the tick's own work
  std::atomic<std::uint64_t> ticks{0};
  std::atomic<std::uint64_t> misses{0};  // ticks whose work ended after the next deadline
  // Of those, the ticks that started more than a tenth of a period after their
  // time (the thread woke or was run late); the others' work was too long.
  std::atomic<std::uint64_t> late_start_misses{0};
  std::atomic<std::uint64_t> worst_tick{0};
  std::atomic<double> worst_period_us{0};
};

/// The polled part of each wait, in ns, for a period and ThreadOptions::spin_us.
std::int64_t SpinNs(std::int64_t period_ns, double spin_us);
/// When the thread stops sleeping and starts polling the clock for the tick due
/// at `deadline`, its last tick's work having ended at `end` (ns, one clock):
/// `spin` before the deadline, but never sooner than a tenth of a period after
/// `end`, and never after the deadline.
std::int64_t PollFrom(std::int64_t end, std::int64_t deadline, std::int64_t period,
                      std::int64_t spin);

class HapticThread {
 public:
  HapticThread(HapticLoop* loop, const ThreadOptions& options);
  ~HapticThread();
  HapticThread(const HapticThread&) = delete;
  HapticThread& operator=(const HapticThread&) = delete;

  /// Starts the thread (the device must be started). Throws std::system_error.
  void Start();
  /// Asks the thread to stop and joins it.
  void Stop();
  /// Waits until the thread ends by itself (max_ticks, device finished).
  void Join();
  bool running() const { return running_.load(std::memory_order_acquire); }

  const TimingStats& stats() const { return stats_; }
  /// What the thread could not have (real-time priority, the pinned core); empty
  /// until the thread has started, then fixed.
  std::string notes() const;
  double rate_hz() const { return loop_->options().rate_hz; }

 private:
  void Run() noexcept;

  HapticLoop* loop_;
  ThreadOptions options_;
  TimingStats stats_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> running_{false};
  std::atomic<bool> notes_ready_{false};
  char notes_[256] = {};
};

}  // namespace sulcus
