#include "core/haptics/haptic_thread.h"

#include <pthread.h>
#include <sched.h>
#include <time.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

namespace sulcus {
namespace {

constexpr std::int64_t kNsPerS = 1'000'000'000;

std::int64_t NowNs() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * kNsPerS + ts.tv_nsec;
}

void SleepUntil(std::int64_t ns) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(ns / kNsPerS);
  ts.tv_nsec = static_cast<long>(ns % kNsPerS);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

// Sleeps until `poll_from`, then polls the clock until `ns`.
void WaitUntil(std::int64_t ns, std::int64_t poll_from) {
  if (poll_from >= ns) return SleepUntil(ns);
  if (poll_from > NowNs()) SleepUntil(poll_from);
  while (NowNs() < ns) {
  }
}

}  // namespace

std::int64_t SpinNs(std::int64_t period_ns, double spin_us) {
  const double us =
      spin_us >= 0 ? spin_us : std::min(0.9e-3 * static_cast<double>(period_ns), 100.0);
  return std::clamp(static_cast<std::int64_t>(1e3 * us), std::int64_t{0},
                    period_ns * 9 / 10);
}

std::int64_t PollFrom(std::int64_t end, std::int64_t deadline, std::int64_t period,
                      std::int64_t spin) {
  if (spin <= 0) return deadline;
  return std::max(deadline - spin, std::min(end + period / 10, deadline));
}

HapticThread::HapticThread(HapticLoop* loop, const ThreadOptions& options)
    : loop_(loop), options_(options) {}

HapticThread::~HapticThread() { Stop(); }

void HapticThread::Start() {
  if (thread_.joinable()) return;
  stop_.store(false);
  running_.store(true, std::memory_order_release);
  thread_ = std::thread([this] { Run(); });
}

void HapticThread::Stop() {
  stop_.store(true, std::memory_order_release);
  Join();
}

void HapticThread::Join() {
  if (thread_.joinable()) thread_.join();
}

std::string HapticThread::notes() const {
  if (!notes_ready_.load(std::memory_order_acquire)) return {};
  return notes_;
}

void HapticThread::Run() noexcept {
  // Ask for what helps, say what was refused, carry on either way.
  std::string refused;
  if (options_.realtime && !options_.free_run) {
    sched_param sp{};
    sp.sched_priority = std::min(80, sched_get_priority_max(SCHED_FIFO));
    if (const int err = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp); err != 0)
      refused += std::string("real-time priority refused (") + std::strerror(err) + "); ";
    const int cores = static_cast<int>(std::thread::hardware_concurrency());
    const int cpu = options_.cpu >= 0 ? options_.cpu : (cores > 0 ? cores - 1 : 0);
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(cpu, &set);
    if (const int err = pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
        err != 0)
      refused +=
          "core " + std::to_string(cpu) + " not pinned (" + std::strerror(err) + "); ";
  }
  if (!refused.empty()) refused += "running without it";
  std::snprintf(notes_, sizeof notes_, "%s", refused.c_str());
  notes_ready_.store(true, std::memory_order_release);

  const double rate = loop_->options().rate_hz > 0 ? loop_->options().rate_hz : 1000.0;
  const auto period = static_cast<std::int64_t>(kNsPerS / rate);
  const std::int64_t spin =
      SpinNs(period, options_.spin_us);  // the polled end of each wait
  std::int64_t deadline = NowNs();       // the scheduled start of the current tick
  std::int64_t last_start = deadline;
  std::uint64_t n = 0;
  while (!stop_.load(std::memory_order_acquire)) {
    const std::int64_t start = NowNs();
    const bool overrun = !options_.free_run && n > 0 &&
                         static_cast<double>(start - deadline) >
                             options_.stall_periods * static_cast<double>(period);
    loop_->Tick(overrun);
    if (options_.sink) options_.sink->Push(loop_->last_record());
    const std::int64_t end = NowNs();

    if (n > 0) {
      const double period_us = static_cast<double>(start - last_start) / 1e3;
      stats_.period_us.Add(period_us);
      if (period_us > stats_.worst_period_us.load(std::memory_order_relaxed)) {
        stats_.worst_period_us.store(period_us, std::memory_order_relaxed);
        stats_.worst_tick.store(n, std::memory_order_relaxed);
      }
    }
    stats_.step_us.Add(static_cast<double>(end - start) / 1e3);
    last_start = start;
    ++n;
    stats_.ticks.store(n, std::memory_order_relaxed);
    if (options_.max_ticks > 0 && n >= options_.max_ticks) break;
    if (options_.stop_when_device_finished && loop_->device_finished()) break;
    if (options_.free_run) continue;

    const std::int64_t late = start - deadline;
    deadline += period;
    if (end > deadline) {
      stats_.misses.fetch_add(1, std::memory_order_relaxed);
      if (late > period / 10)
        stats_.late_start_misses.fetch_add(1, std::memory_order_relaxed);
      // Far behind (a stall, or steps longer than the period): start again from
      // now rather than racing to catch up, and sleep a little anyway: a
      // real-time thread that never sleeps would starve everything on its core.
      if (end - deadline > period) deadline = end;
      SleepUntil(NowNs() + std::max<std::int64_t>(period / 10, 20'000));
      continue;
    }
    WaitUntil(deadline, PollFrom(end, deadline, period, spin));
  }
  running_.store(false, std::memory_order_release);
}

}  // namespace sulcus
