#pragma once
// The grid a device reading is snapped to before the loop uses it: positions in
// steps of 2^-10 mm (0.98 um, thirty times finer than the finest Phantom's encoder
// resolution), orientations as a unit quaternion whose components are steps of
// 2^-20 (about 2e-6 rad). A reading on the grid is a handful of integers, so a
// recording stores it exactly in a few bytes (docs/recordings.md) and a replay
// hands the loop the very pose it used.

#include <array>
#include <cstdint>

#include "core/geometry/transform.h"

namespace sulcus {

inline constexpr double kPositionStepMm = 1.0 / 1024.0;     // 2^-10 mm
inline constexpr double kQuaternionStep = 1.0 / 1048576.0;  // 2^-20

/// A pose on the grid: position in position steps, quaternion (w >= 0) in steps.
struct PoseCode {
  std::array<std::int64_t, 3> p{};
  std::array<std::int64_t, 4> q{};
  bool operator==(const PoseCode&) const = default;
};

/// The code of a pose, or false when the pose cannot be put on the grid (a
/// non-finite number, a position beyond a kilometre). Never throws or allocates.
bool EncodePose(const RigidTransform& X, PoseCode* code) noexcept;

/// The pose a code stands for: always the same doubles for the same code.
RigidTransform DecodePose(const PoseCode& code) noexcept;

}  // namespace sulcus
