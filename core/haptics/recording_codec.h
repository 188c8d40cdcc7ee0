#pragma once
// The tick coding of recording format 3 (docs/recordings.md): each tick as a flags
// byte and the residuals of twenty integer channels (the device pose's code, the
// rendered pose's code, force and torque on their grids) against a straight-line
// prediction from the two ticks before, as zigzag varints; what the prediction
// cannot carry (a skipped tick, a time stamp of its own, events, a pose off the
// grid) follows its flag. The byte stream is then compressed with zstd.

#include <array>
#include <cstdint>
#include <string>

#include "core/haptics/haptic_loop.h"

namespace sulcus {

inline constexpr double kForceStepN = 1.0 / 65536.0;    // 2^-16 N
inline constexpr double kTorqueStepNmm = 1.0 / 4096.0;  // 2^-12 N*mm

/// What both ends remember of the ticks before: the predictions are made from it.
struct TickContext {
  double rate_hz = 1000;
  std::uint64_t tick = 0;
  bool first = true;
  double sample_time_s = 0;
  std::uint32_t buttons = 0;
  std::array<std::array<std::int64_t, 2>, 20> history{};  // the channels' last two
  /// After a tick: what the next one is predicted from (the channels are pushed as
  /// they are coded).
  void Advance(const TickRecord& r) {
    first = false;
    tick = r.tick;
    sample_time_s = r.sample.time_s;
    buttons = r.sample.buttons;
  }
};

class TickEncoder {
 public:
  explicit TickEncoder(double rate_hz) { at_.rate_hz = rate_hz; }
  /// Appends one tick's bytes.
  void Put(const TickRecord& r, std::string* out);

 private:
  TickContext at_;
};

class TickDecoder {
 public:
  explicit TickDecoder(double rate_hz) { at_.rate_hz = rate_hz; }
  enum class Result { kTick, kEnd, kTruncated, kCorrupt };
  /// Reads one tick from [*at, end) and advances *at past it. kEnd when *at == end;
  /// kTruncated when the bytes end inside a tick; kCorrupt (with `why`) when they
  /// cannot be a tick.
  Result Get(const char** at, const char* end, TickRecord* r, std::string* why);

 private:
  TickContext at_;
};

}  // namespace sulcus
