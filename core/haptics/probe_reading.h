#pragma once
// Readings from any clinical stroke. A reading at a site is the deepest dwell
// of the tip in that site's sulcus during one visit, with the force the hand
// held there and the probe's angle, whatever the path:
//
// - A visit starts when the tip locator first puts the tip in the site's sulcus
//   and ends when it has been elsewhere (another site, or none) for kLeaveS
//   (longer than half a period of an 8 Hz tremor): a
//   tremor across a line angle or out of the margin does not end it, and a walk
//   along the sulcus gives each site passed its own visit (the deepest point
//   within its share of the walk).
// - The dwell is the stay at the deepest point of the visit: from the tick the
//   tip was deepest, the ticks until it first moves more than kHeldBandMm away
//   from that point (up the sulcus, or along it to the next stroke); a new
//   deepest more than kRestartMm below the last starts it again (the way down
//   is not the stay at the floor).
// - The held force is the median of the force along the probe over the dwell:
//   a hand's 8-12 Hz tremor of up to 0.15 mm against the firm floor swings the
//   force by a few tenths of a newton about what the hand holds, and the median
//   of that swing is what it holds (the band is wider than the tremor, so no
//   half of the swing is left out). The highest tick within kDwellMm of the
//   deepest point is kept apart as the peak (it is what damages tissue).
// - A visit is a reading when it went at least kMinDepthMm below the margin.
//
// Deterministic over the tick stream (replay is bit for bit), allocation-free
// and non-throwing after construction, so the haptic loop can run it too.

#include <array>
#include <cstdint>

#include "core/haptics/tip_locator.h"

namespace sulcus {

/// One reading: a site's deepest dwell in one visit.
struct ProbeReading {
  int site = -1;            // index into the locator's sites
  double depth_mm = 0;      // the deepest the tip went below the margin
  double held_force_n = 0;  // median of the force along the probe over the dwell
  double peak_force_n = 0;  // the largest raw force along the probe over the dwell
  double angle_deg = 0;     // probe against the long axis at the deepest moment
  std::uint64_t deepest_tick = 0, entered_tick = 0, left_tick = 0;
  int dwell_ticks = 0;  // ticks the dwell's median is taken over
  bool update = false;  // a deeper dwell of a visit already reported (same insertion)
};

class ProbeReadingTracker {
 public:
  static constexpr double kMinDepthMm = 0.5;
  static constexpr double kDwellMm = 0.2;
  static constexpr double kHeldBandMm = 0.4;
  static constexpr double kRestartMm = 0.05;
  static constexpr double kLeaveS = 0.1;
  static constexpr double kBinN = 0.002;  // the held force's resolution
  static constexpr int kBins = 2500;      // 0..5 N; above: the last bin

  explicit ProbeReadingTracker(double rate_hz);

  /// One tick: where the tip is and the raw force along the probe. Returns true
  /// and fills *out when a visit ended with a reading (or a deeper update).
  bool Update(std::uint64_t tick, const TipLocation& where, double force_n,
              ProbeReading* out) noexcept;
  /// Ends the current visit's reading now and seals the visit (the rest of it
  /// reads nothing); false when the tip is in no site or has not gone
  /// kMinDepthMm deep (or nothing is new since the last report).
  bool Complete(std::uint64_t tick, ProbeReading* out) noexcept;
  /// The site of the current visit (-1: none).
  int site() const { return visits_[static_cast<std::size_t>(cur_index_)].site; }
  /// The site the tip was last in (the current visit's, or the last one's
  /// after the tip has come out): the locator's `held`.
  int held() const { return site() >= 0 ? site() : last_in_; }
  void Reset() noexcept;

 private:
  struct Visit {
    int site = -1;
    std::uint64_t entered = 0, deepest_tick = 0, last = 0;
    double deepest = -1e9, restart_at = -1e9, angle = 0, peak = 0;
    Vector3 deepest_W = Vector3::Zero();
    bool dwelling = false;
    int count = 0;
    std::array<std::uint32_t, kBins> hist{};
    bool reported = false, sealed = false;
    double reported_depth = 0;
    void Start(int s, std::uint64_t tick);
    void Add(std::uint64_t tick, const TipLocation& at, double f_raw);
    double Median() const;
  };
  bool Emit(Visit& v, std::uint64_t left, ProbeReading* out) const;
  std::uint64_t leave_ticks_;
  // The visit, and where the tip is while away from it: two slots whose roles
  // swap by index (no copy of their histograms on the haptic thread).
  std::array<Visit, 2> visits_{};
  int cur_index_ = 0;
  Visit& cur() { return visits_[static_cast<std::size_t>(cur_index_)]; }
  Visit& cand() { return visits_[static_cast<std::size_t>(1 - cur_index_)]; }
  std::uint64_t away_since_ = 0;
  bool away_ = false;
  int last_in_ = -1;
};

}  // namespace sulcus
