#include "core/session/session.h"

#include <chrono>
#include <thread>

namespace sulcus {

Session::Session(const CompiledScene& scene, DeviceSpec device,
                 const SessionOptions& options)
    : scene_(scene),
      device_(std::move(device.device)),
      replayed_(std::move(device.replayed)),
      device_name_(options.device_name.empty() ? device.name : options.device_name),
      options_(options) {
  if (!device_) throw std::invalid_argument("a session needs a device");
  LoopOptions lo;
  lo.rate_hz = options.rate_hz > 0 ? options.rate_hz
               : replayed_         ? replayed_->header.rate_hz
                                   : scene.spec.rate_hz;
  lo.force_scale = options.force_scale;
  effects_ = MakeEffects(scene.effects, lo.rate_hz);
  effect_list_ = EffectPointers(effects_);
  loop_ = std::make_unique<HapticLoop>(*scene.model, device_.get(), lo, effect_list_);
  if (!options.record.empty()) {
    RecordingHeader h;
    h.scene_hash = HashFile(scene.spec.file);
    h.rate_hz = lo.rate_hz;
    h.device_name = device_name_;
    h.scene_file = scene.spec.file.string();
    recorder_ = std::make_unique<RecordingWriter>(options.record, h);
  }
}

Session::~Session() {
  try {
    Stop();
  } catch (const std::exception&) {
    // Reported by an explicit Stop(); a destructor must not throw.
  }
}

void Session::AddConsumer(TickConsumer* consumer) { consumers_.push_back(consumer); }

void Session::Start() {
  if (started_) return;
  started_ = true;
  device_->Start();
  ThreadOptions topt;
  topt.realtime = options_.realtime;
  topt.spin_us = options_.spin_us;
  topt.max_ticks = options_.max_ticks;
  topt.sink = this;
  topt.stop_when_device_finished = options_.stop_when_device_finished;
  topt.free_run = options_.free_run;
  thread_ = std::make_unique<HapticThread>(loop_.get(), topt);
  thread_->Start();
}

void Session::Push(const TickRecord& r) noexcept {
  // Free-running (no deadlines), the thread waits for room rather than drop a
  // tick; at its rate it never waits (a full ring is counted as dropped).
  if (options_.free_run) {
    while (ring_.size() >= ring_.capacity()) {
      // A tick made after Stop() was asked for is not the session's: with the
      // ring full it is left out (not counted as dropped).
      if (stopping_.load(std::memory_order_acquire)) return;
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
  }
  ring_.Push(r);
}

void Session::Deliver(const TickRecord& r) {
  if (recorder_) recorder_->PushWaiting(r);
  for (TickConsumer* c : consumers_) c->OnTick(r);
  ++delivered_;
}

std::size_t Session::Pump() {
  std::size_t n = 0;
  while (n < kRingTicks && ring_.Pop(&scratch_)) {
    Deliver(scratch_);
    ++n;
  }
  return n;
}

void Session::End() {
  if (ended_) return;
  ended_ = true;
  device_->Stop();
  for (TickConsumer* c : consumers_) c->OnEnd();
  if (recorder_) recorder_->Finish();
}

void Session::Stop() {
  stopping_.store(true, std::memory_order_release);
  if (thread_) thread_->Stop();
  while (Pump() > 0) {
  }
  if (started_ || delivered_ > 0) End();
}

void Session::RunOffline(const std::function<void(const HapticLoop&)>& each) {
  if (!started_) {
    started_ = true;
    device_->Start();
  }
  const std::uint64_t limit = options_.max_ticks;
  for (std::uint64_t i = 0; (limit == 0 || i < limit) && !device_->finished(); ++i) {
    bool overrun = false;
    if (replayed_ && i < replayed_->frames.size()) {
      // The recorded commands and lateness, as the thread met them.
      const TickRecord& f = replayed_->frames[i];
      overrun = f.overrun;
      ResendCommands(f, loop_.get());
    }
    const auto t0 = std::chrono::steady_clock::now();
    loop_->Tick(overrun);
    last_step_us_ =
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0)
            .count();
    offline_step_us_.Add(last_step_us_);
    Deliver(loop_->last_record());
    if (each) each(*loop_);
  }
  End();
}

}  // namespace sulcus
