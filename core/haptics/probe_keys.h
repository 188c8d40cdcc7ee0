#pragma once
// What the probing keys do, as poses of the probe's tip (the tool frame: the
// tip at its origin, the probe's axis its z toward the handle). The window's
// N, comma/period and T and the scripted "keys" student ask these, so both
// move the probe the same way; each works on the tooth's sulcus ring
// (tip_locator.h), so the tip stays in the sulcus the locator reads.

#include <optional>

#include "core/haptics/tip_locator.h"

namespace sulcus {

/// N: the tip `above_mm` above the margin over site s, in the middle of the
/// sulcus at the site's own angle, the probe along the tooth's long axis
/// leaned `tilt_deg` out from the tooth about the tip (the shaft clear of the
/// crown's bulge, as a clinician holds it).
inline constexpr double kProbeLeanDeg = 4.0;
RigidTransform PoseOverSite(const ProbingSite& s, double above_mm,
                            double tilt_deg = kProbeLeanDeg);

/// The walking keys' step along the sulcus and the lift that goes with it (the
/// press brings the tip back down): the window's and the keys student's.
inline constexpr double kWalkStepMm = 0.4, kWalkLiftMm = 1.0;

/// Comma and period: the tip moved `step_mm` along the sulcus' middle round
/// the tooth (positive: the ring's increasing angle), at the same depth below
/// the margin but above the floor where it steps to, the probe turned with it
/// about the tooth's axis. None when the site has no ring.
std::optional<RigidTransform> WalkAlongSulcus(const ProbingSite& s,
                                              const RigidTransform& X_WT, double step_mm);

/// The world direction of the ring's increasing angle at the tip (horizontal).
Vector3 SulcusTangent(const SulcusRing& r, const Vector3& tip_W);

/// T at interdental site s: the tip taken along the sulcus until it is
/// `under_mm` from the contact's line (under the contact point, where the col
/// is), at its depth but 0.4 mm above the floor
/// there (the press takes it down) and at least TipLocator::kColDepthMm + 0.2
/// deep, and the probe leaned `lean_deg` away from the contact about the tip.
/// None at a mid site or without a ring.
std::optional<RigidTransform> TiltIntoCol(const ProbingSite& s,
                                          const RigidTransform& X_WT,
                                          double lean_deg = 20, double under_mm = 0.5);

}  // namespace sulcus
