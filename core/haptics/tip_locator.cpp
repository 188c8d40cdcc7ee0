#include "core/haptics/tip_locator.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sulcus {

TipLocator::TipLocator(const std::vector<ProbingSite>& sites) : sites_(sites) {
  lines_.reserve(sites.size());
  for (const ProbingSite& s : sites) {
    const Vector3 down = s.floor_W - s.margin_W;
    const double len = down.norm();
    lines_.push_back({len > 0 ? Vector3(down / len) : Vector3::Zero(), len});
  }
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
  // Under a contact two teeth's interproximal sites lie within a millimetre of
  // each other: a tip there reads for the tooth in whose sulcus it is (its
  // side of the cut between the shares, or the sulcus' middle nearer), and for
  // that tooth's site whose line it is nearer.
  TipLocation out;
  out.tip_W = tip;
  double best = 1e9;
  for (int i = 0; i < size(); ++i) {
    double along = 0, off = 0;
    const double past = i == held ? kHoldPastFloorMm : kEnterPastFloorMm;
    if (!Reach(tip, i, past, &along, &off)) continue;
    const ProbingSite& s = sites_[static_cast<std::size_t>(i)];
    const Vector3 from_axis = tip - s.origin_W;
    const double radial = (from_axis - from_axis.dot(s.axis_W) * s.axis_W).norm();
    const double score = std::abs(radial - s.sulcus_r_mm) + 0.25 * off;
    if (score >= best) continue;
    best = score;
    out.site = i;
    out.depth_mm = along;
    out.off_mm = off;
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

double TipLocator::ProbingForce(const Vector3& force_W,
                                const RigidTransform& X_WG) noexcept {
  const double f = force_W.dot(X_WG.rotation().col(2));
  return std::isfinite(f) ? std::max(0.0, f) : 0.0;
}

}  // namespace sulcus
