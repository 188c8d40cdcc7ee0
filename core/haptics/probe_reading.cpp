#include "core/haptics/probe_reading.h"

#include <algorithm>
#include <cmath>

namespace sulcus {

ProbeReadingTracker::ProbeReadingTracker(double rate_hz) {
  const double rate = rate_hz > 0 && std::isfinite(rate_hz) ? rate_hz : 1000.0;
  leave_ticks_ = static_cast<std::uint64_t>(std::max(1.0, std::round(kLeaveS * rate)));
}

void ProbeReadingTracker::Reset() noexcept {
  cur().site = cand().site = -1;
  away_ = false;
  last_in_ = -1;
}

void ProbeReadingTracker::Visit::Start(int s, std::uint64_t tick) {
  site = s;
  entered = deepest_tick = last = tick;
  deepest = restart_at = -1e9;
  angle = peak = 0;
  dwelling = false;
  count = 0;
  hist.fill(0);
  reported = false;
  sealed = false;
  reported_depth = 0;
}

void ProbeReadingTracker::Visit::Add(std::uint64_t tick, const TipLocation& at,
                                     double f_raw) {
  last = tick;
  if (sealed) return;  // charted: the rest of this visit is not its reading
  const double depth = at.depth_mm;
  if (depth > deepest) {
    if (depth > restart_at + kRestartMm) {
      hist.fill(0);
      count = 0;
      peak = 0;
      restart_at = depth;
    }
    deepest = depth;
    deepest_tick = tick;
    deepest_W = at.tip_W;
    angle = at.angle_deg;
    dwelling = true;
  } else if (dwelling && (at.tip_W - deepest_W).norm() > kHeldBandMm) {
    dwelling = false;  // gone from the deepest point: that stay is over
  }
  if (!dwelling) return;
  const double b = std::floor(f_raw / kBinN);
  const int bin = b < kBins - 1 ? static_cast<int>(b) : kBins - 1;
  ++hist[static_cast<std::size_t>(bin)];
  ++count;
  if (depth >= deepest - kDwellMm) peak = std::max(peak, f_raw);
}

double ProbeReadingTracker::Visit::Median() const {
  if (count == 0) return 0;
  const std::uint32_t half = static_cast<std::uint32_t>((count + 1) / 2);
  std::uint32_t seen = 0;
  for (int b = 0; b < kBins; ++b) {
    seen += hist[static_cast<std::size_t>(b)];
    if (seen >= half) return (b + 0.5) * kBinN;
  }
  return (kBins - 0.5) * kBinN;
}

bool ProbeReadingTracker::Emit(Visit& v, std::uint64_t left, ProbeReading* out) const {
  if (v.site < 0 || v.deepest < kMinDepthMm) return false;
  if (v.reported && (v.sealed || v.deepest <= v.reported_depth)) return false;
  out->site = v.site;
  out->depth_mm = v.deepest;
  out->held_force_n = v.Median();
  out->peak_force_n = v.peak;
  out->angle_deg = v.angle;
  out->deepest_tick = v.deepest_tick;
  out->entered_tick = v.entered;
  out->left_tick = left;
  out->dwell_ticks = v.count;
  out->update = v.reported;
  v.reported = true;
  v.reported_depth = v.deepest;
  return true;
}

bool ProbeReadingTracker::Update(std::uint64_t tick, const TipLocation& where,
                                 double force_n, ProbeReading* out) noexcept {
  const double f = std::isfinite(force_n) ? std::max(0.0, force_n) : 0.0;
  if (where.site >= 0) last_in_ = where.site;
  if (where.site == cur().site) {
    away_ = false;
    cand().site = -1;
    if (cur().site >= 0) cur().Add(tick, where, f);
    return false;
  }
  if (cur().site < 0) {  // from nowhere into a site: the visit starts at once
    cur().Start(where.site, tick);
    cur().Add(tick, where, f);
    return false;
  }
  // Away from the visit's site: where the tip is meanwhile is a visit in waiting.
  if (!away_) {
    away_ = true;
    away_since_ = tick;
    cand().site = -1;
  }
  if (where.site != cand().site) {
    if (where.site >= 0)
      cand().Start(where.site, tick);
    else
      cand().site = -1;
  }
  if (cand().site >= 0) cand().Add(tick, where, f);
  if (tick - away_since_ + 1 < leave_ticks_) return false;
  // Gone: the visit ends where the tip left it.
  const bool read = Emit(cur(), away_since_, out);
  cur_index_ = 1 - cur_index_;  // the visit in waiting is the visit now
  cand().site = -1;
  away_ = false;
  return read;
}

bool ProbeReadingTracker::Complete(std::uint64_t tick, ProbeReading* out) noexcept {
  const bool read = Emit(cur(), tick, out);
  if (cur().site >= 0) {
    cur().sealed = true;
    cur().reported = true;
  }
  return read;
}

}  // namespace sulcus
