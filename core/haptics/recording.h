#pragma once
// Recordings: every tick of a session (the loop's inputs and outputs, TickRecord)
// in a versioned binary file, written off the haptic thread; read back, exported
// as CSV, and replayed through the loop, which reproduces the graphic poses and
// wrenches bit for bit with the same build.
//
// File (little-endian): "SULCUSR\n", u32 version, u64 scene hash, f64 rate_hz,
// u32 length + device name, u32 length + scene file name; then, in format 3, one
// zstd stream of coded ticks (recording_codec.h), flushed at every drain so that
// what was written can be read after a crash; format 2 (still read) had plain
// frames, each starting with the marker "FRM1".

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iosfwd>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "core/haptics/haptic_loop.h"

struct ZSTD_CCtx_s;

namespace sulcus {

class TickEncoder;

// 2: typed event payloads, 16 events a tick, 280 bytes a tick; 3: readings on the
// grid, ticks coded as residuals and compressed with zstd (docs/recordings.md).
inline constexpr std::uint32_t kRecordingVersion = 3;

struct RecordingHeader {
  std::uint32_t version = kRecordingVersion;
  std::uint64_t scene_hash = 0;  // FNV-1a of the scene file's bytes
  double rate_hz = 1000;
  std::string device_name;
  std::string scene_file;
};

/// A bad or unreadable recording: names the file, the byte and what was expected.
class RecordingError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Writes ticks from the haptic thread: Push copies into a fixed ring (never
/// blocks; a full ring drops the tick and counts it); a writer thread drains it.
class RecordingWriter final : public TickSink {
 public:
  /// Opens (creates or truncates) the file; throws RecordingError.
  RecordingWriter(const std::filesystem::path& file, const RecordingHeader& header);
  ~RecordingWriter();
  void Push(const TickRecord& r) noexcept override { ring_.Push(r); }
  /// Off the haptic thread (offline runs, a session's pump): waits for room
  /// instead of dropping the tick.
  void PushWaiting(const TickRecord& r);
  /// Drains what is left, closes the file; throws RecordingError on a write error.
  void Finish();
  std::uint64_t written() const { return written_.load(); }
  std::uint64_t dropped() const { return ring_.dropped(); }

 private:
  void Drain();
  void Compress(const std::string& raw, bool end);
  std::filesystem::path file_;
  std::FILE* out_ = nullptr;
  std::unique_ptr<TickEncoder> encoder_;
  ZSTD_CCtx_s* zstd_ = nullptr;
  std::vector<char> compressed_;  // the compressor's output, sized once
  SpscRing<TickRecord, 8192> ring_;
  std::thread writer_;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> written_{0};
  std::atomic<bool> write_failed_{false};
};

struct Recording {
  RecordingHeader header;
  std::vector<TickRecord> frames;
  std::uint64_t file_bytes = 0;  // the file's size, for its bytes a tick
  std::string warning;  // e.g. a truncated last frame (the frames before it are kept)
};

/// Reads a whole recording. Throws RecordingError for a file that is not a
/// recording, of another version, or corrupt before its first frame.
Recording ReadRecording(const std::filesystem::path& file);

/// One line per tick: poses (position and quaternion), wrench, flags, events.
void ExportCsv(const Recording& recording, std::ostream& out);

/// Plays a recording's device readings back, one per tick, in order.
class ReplayDevice final : public Device {
 public:
  explicit ReplayDevice(const Recording& recording);
  const DeviceCaps& caps() const override { return caps_; }
  bool Read(double t_s, DeviceSample* out) noexcept override;
  void Write(const Vector3&, const Vector3&) noexcept override {}
  bool finished() const noexcept override { return next_ >= recording_.frames.size(); }
  std::size_t next_frame() const { return next_; }

 private:
  const Recording& recording_;
  DeviceCaps caps_;
  std::size_t next_ = 0;
};

/// Replays a recording through a loop as fast as possible, with the recorded
/// lateness and commands, calling `each(frame index, loop)` after every tick.
/// Sends a recorded tick's commands to the loop again, as the thread met them.
inline void ResendCommands(const TickRecord& f, HapticLoop* loop) {
  for (int e = 0; e < f.num_events; ++e)
    if (f.events[e].kind == EventKind::kCommand)
      loop->Send({static_cast<HapticCommand::Kind>(f.events[e].payload.command.command),
                  f.events[e].payload.command.value});
}

template <class Each>
void ReplayOffline(const Recording& recording, HapticLoop* loop, Each each) {
  for (std::size_t i = 0; i < recording.frames.size(); ++i) {
    const TickRecord& f = recording.frames[i];
    ResendCommands(f, loop);
    loop->Tick(f.overrun);
    each(i, *loop);
  }
}

}  // namespace sulcus
