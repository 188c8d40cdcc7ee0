#pragma once
// A Session owns one run (docs/architecture.md, "A run: the Session"): the
// compiled scene, the device, the scene's effects, the haptic loop, the thread
// (live) or the offline ticker, and the recorder. Every tick's record (device
// pose, graphic pose, force, typed events) goes, off the haptic thread and in
// tick order, to every consumer: the recorder, a lesson, the window, a test.
//
// Live: the haptic thread pushes each record into a fixed ring (never blocks);
// the owner calls Pump() from its own thread (the window's timer, the CLI's
// loop), which hands the records to the consumers. A ring that overflows
// because nobody pumped counts the lost ticks (dropped_ticks()), never silently.
// Offline: RunOffline() ticks on the caller's thread as fast as possible and
// hands each record over as it is made; a replayed recording's commands and
// lateness are re-applied, so the same consumers see the same stream.

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/haptics/haptic_thread.h"
#include "core/haptics/recording.h"
#include "core/scene/scene.h"

namespace sulcus {

/// Receives the tick stream, in order, never on the haptic thread.
class TickConsumer {
 public:
  virtual ~TickConsumer() = default;
  virtual void OnTick(const TickRecord& r) = 0;
  /// After the last tick (Stop or the end of RunOffline).
  virtual void OnEnd() {}
};

struct SessionOptions {
  double rate_hz = 0;           // 0: the scene's (a replay: the recording's)
  std::uint64_t max_ticks = 0;  // 0: until Stop() or the device has no more input
  bool realtime = true;         // ask for real-time priority (live)
  double spin_us =
      -1;  // the haptic thread's polled end of each wait (ThreadOptions::spin_us)
  bool stop_when_device_finished =
      true;  // live: end when a script or replay ends (the window keeps going)
  bool free_run = false;  // live: no sleeping between ticks (a scripted student or replay
                          // as fast as possible)
  std::filesystem::path record;  // record every tick here (empty: no recording)
  std::string device_name;       // for the recording's header
  double force_scale = 1.0;
};

/// A device made from a command-line spelling (MakeDevice).
struct DeviceSpec {
  std::unique_ptr<Device> device;
  std::unique_ptr<Recording> replayed;  // for replay:FILE, the recording it plays
  std::string name;  // what to call it ("scripted:insert", "replay of scripted:poke")
  std::vector<std::string>
      notes;  // warnings to show (a replay of another scene version, ...)
};

/// A device's name as the command line, the window and an attempt marker spell
/// it, parsed in one place: "mouse" (the window's keys and mouse),
/// "scripted:NAME" or "scripted:FILE.csv", "replay:FILE", "student:NAME" (a
/// scripted student, in a lesson).
struct DeviceName {
  enum class Kind { kMouse, kScripted, kScriptFile, kReplay, kStudent };
  Kind kind = Kind::kMouse;
  std::string what;  // the script, file or student's name
  /// The file the device reads (a CSV or a recording), else empty.
  std::filesystem::path file() const {
    return kind == Kind::kScriptFile || kind == Kind::kReplay ? what : "";
  }
};
/// Throws std::invalid_argument naming the spellings for anything else.
DeviceName ParseDeviceName(const std::string& spelling);

/// What kind of device a name (a spelling, or a recording's device name) is:
/// "keys" (the window's mouse and keyboard), "scripted" (a script or a scripted
/// student), "replay" (a recording played back) or "haptic" (anything else: a
/// haptic device). A scripted or replayed attempt is not a student's own work.
std::string DeviceKindOf(const std::string& device_name);

/// "scripted:NAME" (a named trajectory on `object`, -1: the first tooth; see
/// MakeScript), "scripted:FILE.csv" or "replay:FILE". Throws std::invalid_argument
/// for another spelling, RecordingError or std::runtime_error for a bad file.
DeviceSpec MakeDevice(const std::string& spelling, const CompiledScene& scene,
                      double seconds, std::uint64_t seed = 1, int object = -1);

class Session final : private TickSink {
 public:
  /// The scene must outlive the session. A replayed recording (DeviceSpec) is
  /// passed along so that its commands and lateness are re-applied offline.
  Session(const CompiledScene& scene, DeviceSpec device,
          const SessionOptions& options = {});
  ~Session() override;
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  /// Consumers get every tick from the next one on; not owned.
  void AddConsumer(TickConsumer* consumer);

  /// Starts the device and the haptic thread. Throws DeviceError, std::system_error.
  void Start();
  /// Live: hands the records made since the last call to the consumers, at most
  /// a ring's worth (16 s at 1 kHz), so that a free-running thread that refills
  /// the ring as fast as it drains cannot hold the caller; returns how many.
  /// Call it often (every few ms to every 100 ms).
  std::size_t Pump();
  /// Live: true while the thread runs.
  bool running() const { return thread_ && thread_->running(); }
  /// Stops the thread, pumps what is left, writes the recording out and tells
  /// the consumers the stream ended. Idempotent. Throws RecordingError when the
  /// recording could not be written (the consumers have their ticks regardless).
  void Stop();

  /// No thread, no clock: ticks until max_ticks or the device is finished,
  /// handing each record to the consumers, then ends like Stop(). `each` runs
  /// after every tick (tests read the loop's data there).
  void RunOffline(const std::function<void(const HapticLoop&)>& each = {});

  HapticLoop& loop() { return *loop_; }
  const HapticLoop& loop() const { return *loop_; }
  const CompiledScene& scene() const { return scene_; }
  const HapticThread* thread() const { return thread_.get(); }
  /// Step time of the offline ticks (the thread keeps its own statistics).
  const TimeHistogram& offline_step_us() const { return offline_step_us_; }
  /// The last offline tick's step time (us).
  double last_step_us() const { return last_step_us_; }
  double rate_hz() const { return loop_->options().rate_hz; }
  std::uint64_t ticks_delivered() const { return delivered_; }
  std::uint64_t dropped_ticks() const { return ring_.dropped(); }
  const std::string& device_name() const { return device_name_; }
  const RecordingWriter* recorder() const { return recorder_.get(); }
  /// The effects in the loop (an effect the scene does not name is not here).
  const std::vector<std::unique_ptr<LoopEffect>>& effects() const { return effects_; }

 private:
  void Push(const TickRecord& r) noexcept override;
  void Deliver(const TickRecord& r);
  void End();

  const CompiledScene& scene_;
  std::unique_ptr<Device> device_;
  std::unique_ptr<Recording> replayed_;
  std::string device_name_;
  SessionOptions options_;
  std::vector<std::unique_ptr<LoopEffect>> effects_;
  std::vector<LoopEffect*> effect_list_;
  std::unique_ptr<HapticLoop> loop_;
  std::unique_ptr<HapticThread> thread_;
  std::unique_ptr<RecordingWriter> recorder_;
  std::vector<TickConsumer*> consumers_;
  static constexpr std::size_t kRingTicks = 16384;
  SpscRing<TickRecord, kRingTicks> ring_;
  TickRecord scratch_;
  TimeHistogram offline_step_us_;
  double last_step_us_ = 0;
  std::uint64_t delivered_ = 0;
  bool started_ = false, ended_ = false;
  std::atomic<bool> stopping_{false};
};

}  // namespace sulcus
