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

class TickEncoder {
 public:
  explicit TickEncoder(double rate_hz) : rate_hz_(rate_hz) {}
  /// Appends one tick's bytes.
  void Put(const TickRecord& r, std::string* out);

 private:
  double rate_hz_;
  std::uint64_t tick_ = 0;
  bool first_ = true;
  double sample_time_s_ = 0;
  std::uint32_t buttons_ = 0;
  std::array<std::array<std::int64_t, 2>, 20> history_{};
};

class TickDecoder {
 public:
  explicit TickDecoder(double rate_hz) : rate_hz_(rate_hz) {}
  enum class Result { kTick, kEnd, kTruncated, kCorrupt };
  /// Reads one tick from [*at, end) and advances *at past it. kEnd when *at == end;
  /// kTruncated when the bytes end inside a tick; kCorrupt (with `why`) when they
  /// cannot be a tick.
  Result Get(const char** at, const char* end, TickRecord* r, std::string* why);

 private:
  double rate_hz_;
  std::uint64_t tick_ = 0;
  bool first_ = true;
  double sample_time_s_ = 0;
  std::uint32_t buttons_ = 0;
  std::array<std::array<std::int64_t, 2>, 20> history_{};
};

}  // namespace sulcus
