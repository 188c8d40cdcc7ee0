#include "core/haptics/tip_locator.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sulcus {

namespace {

constexpr double kPi = std::numbers::pi;

double Wrap(double a) {
  a = std::fmod(a, 2 * kPi);
  return a < 0 ? a + 2 * kPi : a;
}

bool Interdental(int site) { return site != 1 && site != 4; }
bool Mesial(int site) { return site == 0 || site == 3; }

}  // namespace

int SulcusRing::SegmentAt(double phi) const {
  const int n = size();
  if (n == 0) return 0;
  return static_cast<int>(std::lround(Wrap(phi) / (2 * kPi) * n)) % n;
}

void SulcusRing::MakeZones() {
  const int n = size();
  arc_mm.assign(static_cast<std::size_t>(n), 0.0);
  length_mm = 0;
  if (n < 4) return;
  auto at = [&](int k) {
    const double th = 2 * kPi * k / n;
    const double r = sulcus_r[static_cast<std::size_t>(k % n)];
    return Vector3(r * std::cos(th), r * std::sin(th), 0);
  };
  for (int k = 1; k < n; ++k)
    arc_mm[static_cast<std::size_t>(k)] =
        arc_mm[static_cast<std::size_t>(k - 1)] + (at(k) - at(k - 1)).norm();
  length_mm = arc_mm.back() + (at(0) - at(n - 1)).norm();
  // The angle at which the length from angle 0 reaches `len` (linear within a
  // segment).
  auto angle_at = [&](double len) {
    for (int k = 1; k <= n; ++k) {
      const double hi = k < n ? arc_mm[static_cast<std::size_t>(k)] : length_mm;
      const double lo = arc_mm[static_cast<std::size_t>(k - 1)];
      if (len <= hi) {
        const double t = hi > lo ? (len - lo) / (hi - lo) : 0.0;
        return 2 * kPi * (k - 1 + t) / n;
      }
    }
    return 2 * kPi;
  };
  // The col's midline on each interdental side: from the contact's line back
  // toward the zone, the first angle whose sulcus (half way down) is on the
  // tooth's side of the cut toward that neighbour.
  const Matrix3 R = X_RW.rotation();
  for (const int s : {0, 2, 3, 5}) {
    const double contact = Mesial(s) ? 0.0 : kPi;
    col_phi[static_cast<std::size_t>(s)] = contact;
    int cut = -1;
    for (int c = 0; c < num_cuts; ++c) {
      Vector3 toward = R * cut_n_W[static_cast<std::size_t>(c)];
      if (mirrored) toward.x() = -toward.x();
      if ((Mesial(s) && toward.x() > 0.3) || (!Mesial(s) && toward.x() < -0.3)) cut = c;
    }
    if (cut < 0) continue;
    const Vector3& q = cut_q_W[static_cast<std::size_t>(cut)];
    const Vector3& nw = cut_n_W[static_cast<std::size_t>(cut)];
    for (double a = 0; a < kPi / 2; a += kPi / 720) {
      const double phi = contact + TowardZone(s) * a;
      const int k = SegmentAt(phi);
      const double mid = 0.5 * (margin_z[static_cast<std::size_t>(k)] -
                                floor_z[static_cast<std::size_t>(k)]);
      if ((PointAt(phi, mid) - q).dot(nw) <= 0) {
        col_phi[static_cast<std::size_t>(s)] = phi;
        break;
      }
    }
  }
  // Each half of the outline, from the mesial contact's line round to the
  // distal one, in three equal lengths (the interdental sites take their
  // thirds and the interproximal area up to the contact's line, the col
  // included).
  const double half = arc_mm[static_cast<std::size_t>(n / 2)];
  const double oral = length_mm - half;
  facial_from = angle_at(half / 3);
  facial_to = angle_at(2 * half / 3);
  oral_from = angle_at(half + oral / 3);
  oral_to = angle_at(half + 2 * oral / 3);
}

double SulcusRing::TowardZone(int site) {
  return Mesial(site) == (site < 3) ? 1.0 : -1.0;
}

int SulcusRing::ZoneAt(double phi) const {
  const double a = Wrap(phi);
  if (a < kPi) return a < facial_from ? 0 : a < facial_to ? 1 : 2;
  return a < oral_from ? 5 : a < oral_to ? 4 : 3;
}

Vector3 SulcusRing::ToRing(const Vector3& p_W) const {
  Vector3 p = X_RW * p_W;
  if (mirrored) p.x() = -p.x();
  return p;
}

Vector3 SulcusRing::PointAt(double phi, double depth_mm, double outward_mm) const {
  const int k = SegmentAt(phi);
  const double r = sulcus_r[static_cast<std::size_t>(k)] + outward_mm;
  Vector3 p(r * std::cos(phi), r * std::sin(phi),
            margin_z[static_cast<std::size_t>(k)] - depth_mm);
  if (mirrored) p.x() = -p.x();
  return X_RW.inverse() * p;
}

Vector3 SulcusRing::AxisW() const {
  return X_RW.rotation().transpose() * Vector3::UnitZ();
}

double SulcusRing::ToContactMm(double phi, int site) const {
  if (size() == 0 || length_mm <= 0 || !Interdental(site)) return -1;
  const double col = col_phi[static_cast<std::size_t>(site)];
  // Past the col's midline (toward the contact's line): in the col.
  if (std::remainder(phi - col, 2 * kPi) * TowardZone(site) <= 0) return 0;
  double d = std::abs(arc_mm[static_cast<std::size_t>(SegmentAt(phi))] -
                      arc_mm[static_cast<std::size_t>(SegmentAt(col))]);
  return std::min(d, length_mm - d);
}

TipLocator::TipLocator(const std::vector<ProbingSite>& sites) : sites_(sites) {
  lines_.reserve(sites.size());
  for (int i = 0; i < static_cast<int>(sites.size()); ++i) {
    const ProbingSite& s = sites[static_cast<std::size_t>(i)];
    const Vector3 down = s.floor_W - s.margin_W;
    const double len = down.norm();
    lines_.push_back({len > 0 ? Vector3(down / len) : Vector3::Zero(), len});
    if (!s.ring || s.ring->size() == 0 || s.site < 0 || s.site > 5) continue;
    auto it = std::find_if(rings_.begin(), rings_.end(),
                           [&](const Ring& r) { return r.ring == s.ring.get(); });
    if (it == rings_.end()) {
      rings_.push_back({s.ring.get(), {-1, -1, -1, -1, -1, -1}});
      it = rings_.end() - 1;
    }
    it->site[static_cast<std::size_t>(s.site)] = i;
  }
}

bool TipLocator::Cut(const SulcusRing& r, const Vector3& tip) const {
  for (int c = 0; c < r.num_cuts; ++c)
    if ((tip - r.cut_q_W[static_cast<std::size_t>(c)])
            .dot(r.cut_n_W[static_cast<std::size_t>(c)]) > 0)
      return true;
  return false;
}

bool TipLocator::Reach(const Vector3& tip, int i, double past, double* along,
                       double* off) const {
  const ProbingSite& s = sites_[static_cast<std::size_t>(i)];
  const Line& l = lines_[static_cast<std::size_t>(i)];
  if (l.len <= 0) return false;
  *along = (tip - s.margin_W).dot(l.u);
  if (*along < -kAboveMarginMm || *along > l.len + past) return false;
  *off = (tip - s.margin_W - *along * l.u).norm();
  if (*off > kRadiusMm) return false;
  for (int c = 0; c < s.num_cuts; ++c)
    if ((tip - s.cut_q_W[static_cast<std::size_t>(c)])
            .dot(s.cut_n_W[static_cast<std::size_t>(c)]) > 0)
      return false;
  return true;
}

bool TipLocator::Near(const RigidTransform& X_WG, int i) const noexcept {
  double along = 0, off = 0;
  return i >= 0 && i < size() &&
         Reach(X_WG.translation(), i, kEnterPastFloorMm, &along, &off);
}

TipLocation TipLocator::Locate(const RigidTransform& X_WG, int held) const noexcept {
  const Vector3 tip = X_WG.translation();
  TipLocation out;
  out.tip_W = tip;
  double best = 1e9;
  const SulcusRing* held_ring = held >= 0 && held < size()
                                    ? sites_[static_cast<std::size_t>(held)].ring.get()
                                    : nullptr;
  // The teeth with a ring: the one whose sulcus' middle runs nearest the tip
  // at its angle; the site is the zone that holds the angle.
  struct Fallback {
    int site = -1;
    double depth = 0, phi = 0;
    int zone = 0;
    const SulcusRing* ring = nullptr;
    double pocket = 0;
  } fallback;
  double fallback_radial = 1e9;
  for (const Ring& g : rings_) {
    const SulcusRing& r = *g.ring;
    const Vector3 p = r.ToRing(tip);
    const double phi = Wrap(std::atan2(p.y(), p.x()));
    const int k = r.SegmentAt(phi);
    const double radial =
        std::abs(std::hypot(p.x(), p.y()) - r.sulcus_r[static_cast<std::size_t>(k)]);
    if (radial > kRadiusMm) continue;
    const double margin = r.margin_z[static_cast<std::size_t>(k)];
    const double depth = margin - p.z();
    const double pocket = margin - r.floor_z[static_cast<std::size_t>(k)];
    const double past = g.ring == held_ring ? kHoldPastFloorMm : kEnterPastFloorMm;
    if (depth < -kAboveMarginMm || depth > pocket + past) continue;
    const int zone = r.ZoneAt(phi);
    // Past the cut between this tooth's gingiva and the neighbour's the
    // sulcus is the neighbour's; but under the contact the two sulci are one
    // space (the col): a tip that came along its tooth's sulcus into the
    // interproximal area stays with its site up to the contact's line.
    const bool past_cut = Cut(r, tip);
    const int i = g.site[static_cast<std::size_t>(zone)];
    if (i < 0) continue;
    if (past_cut && !(g.ring == held_ring && Interdental(zone))) {
      // Past the cut and not the col it came along: this tooth's only if no
      // tooth's sulcus claims the point on its own side (a crowded or curved
      // arch's cut can pass inside a tooth's own sulcus; what lies past it is
      // read as this tooth's when no neighbour's sulcus is there).
      if (radial < fallback_radial) {
        fallback_radial = radial;
        fallback = {i, depth, phi, zone, &r, pocket};
      }
      continue;
    }
    if (radial >= best) continue;
    best = radial;
    out.site = i;
    out.depth_mm = depth;
    out.phi = phi;
    out.to_contact_mm = Interdental(zone) ? r.ToContactMm(phi, zone) : -1;
    // In the col (past the cut, or past the col's midline where the sulcus
    // meets the neighbour's) the floor is the neighbour's gingiva's as much as
    // this tooth's: the depth is read against the tooth's own floor there, no
    // deeper (a deeper neighbour's pocket is not this site's).
    out.past_cut = past_cut || out.to_contact_mm == 0;
    if (out.past_cut) out.depth_mm = std::min(depth, pocket);
    const ProbingSite& s = sites_[static_cast<std::size_t>(i)];
    const Line& l = lines_[static_cast<std::size_t>(i)];
    const double along = (tip - s.margin_W).dot(l.u);
    out.off_mm = (tip - s.margin_W - along * l.u).norm();
  }
  if (out.site < 0 && fallback.site >= 0) {
    const ProbingSite& s = sites_[static_cast<std::size_t>(fallback.site)];
    const Line& l = lines_[static_cast<std::size_t>(fallback.site)];
    best = fallback_radial;
    out.site = fallback.site;
    out.depth_mm = fallback.depth;
    out.phi = fallback.phi;
    out.to_contact_mm = Interdental(fallback.zone)
                            ? fallback.ring->ToContactMm(fallback.phi, fallback.zone)
                            : -1;
    // Past the cut, read against the tooth's own floor there, as in the col.
    out.past_cut = true;
    out.depth_mm = std::min(fallback.depth, fallback.pocket);
    const double along = (tip - s.margin_W).dot(l.u);
    out.off_mm = (tip - s.margin_W - along * l.u).norm();
  }
  // Sites without a ring: the nearest line. Under a contact two teeth's
  // interproximal sites lie within a millimetre of each other: a tip there
  // reads for the tooth in whose sulcus it is (its side of the cut between
  // the shares, or the sulcus' middle nearer), and for that tooth's site whose
  // line it is nearer.
  for (int i = 0; i < size(); ++i) {
    const ProbingSite& s = sites_[static_cast<std::size_t>(i)];
    if (s.ring) continue;
    double along = 0, off = 0;
    const double past = i == held ? kHoldPastFloorMm : kEnterPastFloorMm;
    if (!Reach(tip, i, past, &along, &off)) continue;
    const Vector3 from_axis = tip - s.origin_W;
    const double radial = (from_axis - from_axis.dot(s.axis_W) * s.axis_W).norm();
    const double score = std::abs(radial - s.sulcus_r_mm) + 0.25 * off;
    if (score >= best) continue;
    best = score;
    out.site = i;
    out.depth_mm = along;
    out.off_mm = off;
    out.phi = 0;
    out.to_contact_mm = -1;
    out.past_cut = false;
  }
  if (out.site >= 0) {
    const Vector3 tool_axis = X_WG.rotation().col(2);
    const double c = std::clamp(
        std::abs(tool_axis.dot(sites_[static_cast<std::size_t>(out.site)].axis_W)), 0.0,
        1.0);
    out.angle_deg = std::acos(c) * 180.0 / std::numbers::pi;
  }
  return out;
}

bool TipLocator::UnderContact(const TipLocation& at, double reach_mm) noexcept {
  return at.site >= 0 && at.to_contact_mm >= 0 && at.depth_mm >= kColDepthMm &&
         at.to_contact_mm <= reach_mm;
}

double TipLocator::ProbingForce(const Vector3& force_W,
                                const RigidTransform& X_WG) noexcept {
  const double f = force_W.dot(X_WG.rotation().col(2));
  return std::isfinite(f) ? std::max(0.0, f) : 0.0;
}

}  // namespace sulcus
