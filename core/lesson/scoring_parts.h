#pragma once
// What the lesson's state machine and its two scorers share
// (core/lesson/lesson.cpp, score_probing.cpp, score_inspection.cpp): not for
// use outside the lesson.

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "core/lesson/lesson.h"

namespace sulcus::lesson_detail {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = 180.0 / kPi;
// The walking stroke's arc per surface, in the tooth frame (0 = mesial, 90 = buccal):
// from 15 degrees off one contact to 15 degrees off the other.
constexpr double kArcFromDeg = 15, kArcToDeg = 165;
// The walking stroke's arc stops this short of the col's midline on each side.
constexpr double kColMarginMm = 0.5;
constexpr double kStrokeHysteresisMm = 0.3;

inline std::string Format(const char* fmt, auto... args) {
  char buf[320];
  std::snprintf(buf, sizeof buf, fmt, args...);
  return buf;
}

inline double AngleDistance(double a, double b) {
  double d = std::fmod(std::abs(a - b), 2 * kPi);
  return d > kPi ? 2 * kPi - d : d;
}

// Segment k's angle in degrees, 0..360.
inline double SegmentDeg(int k, int n) { return 360.0 * k / n; }

inline RubricLine Line(const char* category, const SiteRef* site, int fdi,
                       RubricLine::Status status, double credit, std::string message,
                       std::uint64_t tick) {
  RubricLine l;
  l.category = category;
  if (site) l.site = *site;
  l.fdi = site ? site->fdi : fdi;
  l.status = status;
  l.credit = credit;
  l.message = std::move(message);
  l.tick = tick;
  return l;
}

using S = RubricLine::Status;

// A line's credit by its status: full, half, none.
inline double Credit(S status) {
  return status == S::kPass ? 1 : status == S::kPartial ? 0.5 : 0;
}

}  // namespace sulcus::lesson_detail
