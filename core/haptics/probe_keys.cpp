#include "core/haptics/probe_keys.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sulcus {

namespace {

constexpr double kPi = std::numbers::pi;

// A rotation taking the probe's axis to `up` (unit), the rest turned the
// least.
RigidTransform Along(const Vector3& up, const Vector3& tip) {
  return RigidTransform(Quaternion::FromTwoVectors(Vector3::UnitZ(), up), tip);
}

double PhiOf(const SulcusRing& r, const Vector3& p_W) {
  const Vector3 p = r.ToRing(p_W);
  return std::atan2(p.y(), p.x());
}

}  // namespace

RigidTransform PoseOverSite(const ProbingSite& s, double above_mm, double tilt_deg) {
  if (!s.ring || s.ring->size() == 0) {
    const Vector3 down = (s.floor_W - s.margin_W).normalized();
    return Along(-down, s.margin_W - above_mm * down);
  }
  const SulcusRing& r = *s.ring;
  const double phi = PhiOf(r, s.margin_W);
  const Vector3 tip = r.PointAt(phi, -above_mm);
  // Leaned out from the tooth about the tip, as a clinician clears the
  // crown's bulge with the shaft while the tip follows the root.
  Vector3 out = r.PointAt(phi, -above_mm, 1.0) - tip;
  out -= r.AxisW() * out.dot(r.AxisW());
  const double lean = tilt_deg * kPi / 180;
  const Vector3 up =
      out.norm() > 1e-9
          ? Vector3(std::cos(lean) * r.AxisW() + std::sin(lean) * out.normalized())
          : r.AxisW();
  return Along(up.normalized(), tip);
}

Vector3 SulcusTangent(const SulcusRing& r, const Vector3& tip_W) {
  const double phi = PhiOf(r, tip_W), e = 1e-3;
  Vector3 t = r.PointAt(phi + e, 0) - r.PointAt(phi - e, 0);
  const Vector3 axis = r.AxisW();
  t -= axis * t.dot(axis);
  return t.norm() > 1e-12 ? Vector3(t.normalized()) : axis.unitOrthogonal();
}

std::optional<RigidTransform> WalkAlongSulcus(const ProbingSite& s,
                                              const RigidTransform& X_WT,
                                              double step_mm) {
  if (!s.ring || s.ring->size() == 0) return std::nullopt;
  const SulcusRing& r = *s.ring;
  const Vector3 tip = X_WT.translation();
  const Vector3 p = r.ToRing(tip);
  const double phi = std::atan2(p.y(), p.x());
  const int k = r.SegmentAt(phi);
  const double depth = r.margin_z[static_cast<std::size_t>(k)] - p.z();
  const double radius = std::max(0.5, r.sulcus_r[static_cast<std::size_t>(k)]);
  const double next = phi + step_mm / radius;
  // Never below the floor where it steps to (a shallower site ahead): the
  // press takes the tip down to it.
  const int kn = r.SegmentAt(next);
  const double floor_there =
      r.margin_z[static_cast<std::size_t>(kn)] - r.floor_z[static_cast<std::size_t>(kn)];
  const Vector3 to = r.PointAt(next, std::min(depth, floor_there - 0.2));
  // Turned about the tooth's axis by the angle walked (the arch's mirror
  // turns the other way in the world).
  const double turn = (r.mirrored ? -1.0 : 1.0) * (next - phi);
  const Quaternion q(Eigen::AngleAxisd(turn, r.AxisW()));
  return RigidTransform(q * X_WT.rotation(), to);
}

std::optional<RigidTransform> TiltIntoCol(const ProbingSite& s,
                                          const RigidTransform& X_WT, double lean_deg,
                                          double under_mm) {
  if (!s.ring || s.ring->size() == 0 || s.site == 1 || s.site == 4) return std::nullopt;
  const SulcusRing& r = *s.ring;
  const bool mesial = s.site == 0 || s.site == 3, facial = s.site < 3;
  // The col's side of the zone: facial sites lie at angles in (0, pi), oral
  // ones in (pi, 2 pi).
  const double toward_zone = (mesial == facial) ? 1.0 : -1.0;
  const Vector3 tip = X_WT.translation();
  const Vector3 p = r.ToRing(tip);
  const double phi = std::atan2(p.y(), p.x());
  const double depth_now = r.margin_z[static_cast<std::size_t>(r.SegmentAt(phi))] - p.z();
  const double col = r.col_phi[static_cast<std::size_t>(s.site)];
  const double rcol =
      std::max(0.5, r.sulcus_r[static_cast<std::size_t>(r.SegmentAt(col))]);
  const double go_to =
      r.ToContactMm(phi, s.site) > under_mm ? col + toward_zone * under_mm / rcol : phi;
  const int k = r.SegmentAt(go_to);
  const double pocket =
      r.margin_z[static_cast<std::size_t>(k)] - r.floor_z[static_cast<std::size_t>(k)];
  // Above the floor there (the press takes it down to it), and deep enough
  // to be under the contact.
  const double depth = std::clamp(std::min(depth_now, pocket - 0.4),
                                  TipLocator::kColDepthMm + 0.2, std::max(1.2, pocket));
  const Vector3 at = r.PointAt(go_to, depth);
  // Away from the contact along the sulcus: the ring's tangent pointing from
  // the contact into the zone.
  const Vector3 away = SulcusTangent(r, at) * toward_zone;
  const Vector3 axis = r.AxisW();
  const double lean = lean_deg * kPi / 180;
  // The handle leans away from the contact; the tip reaches under it.
  const Vector3 up = std::cos(lean) * axis + std::sin(lean) * away;
  return Along(up.normalized(), at);
}

}  // namespace sulcus
