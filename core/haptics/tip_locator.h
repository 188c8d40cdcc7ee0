#pragma once
// Where the probe's tip is: the one answer to "which site's sulcus holds the tip,
// how deep along that site's line, at what angle". The probing_depth effect, the
// lesson (its readings, its "you are in the sulcus of"), the window's panel and
// the report all ask this locator; nothing else decides where the tip is.

#include <array>
#include <vector>

#include "core/geometry/transform.h"
#include "core/geometry/types.h"

namespace sulcus {

/// A probing site in the world: the sulcus' middle at the margin and at the floor.
struct ProbingSite {
  int tooth = -1;  // object index of the tooth
  int fdi = 0;     // its FDI number
  int site = 0;    // 0..5: MB, B, DB, ML, L, DL
  Vector3 margin_W = Vector3::Zero(), floor_W = Vector3::Zero();
  Vector3 axis_W = Vector3::UnitZ();   // the tooth's long axis (unit, toward the crown)
  Vector3 origin_W = Vector3::Zero();  // a point on that axis (the tooth frame's origin)
  double sulcus_r_mm = 0;  // the site's line from the axis (the sulcus' middle)
  // In one gingiva per arch, the cuts between this tooth's share and its
  // neighbours' (a point and the normal toward the neighbour): a tip beyond
  // one is in the neighbour's sulcus, not this tooth's.
  std::array<Vector3, 2> cut_q_W{}, cut_n_W{};
  int num_cuts = 0;
  double pocket_mm = 0;
  bool bleeding = false;
};

/// Where the tip is on one tick.
struct TipLocation {
  int site = -1;         // index into the locator's sites; -1: in no site's sulcus
  double depth_mm = 0;   // below the margin along the site's line (negative: above it)
  double off_mm = 0;     // from the site's line
  double angle_deg = 0;  // the probe's axis against the tooth's long axis
  Vector3 tip_W = Vector3::Zero();  // where the tip is
};

/// The sites' lines, precomputed. Locate() allocates nothing and never throws.
class TipLocator {
 public:
  /// A tip belongs to a site when it is within kRadiusMm of the site's line,
  /// from kAboveMarginMm above the margin to kEnterPastFloorMm past the floor
  /// (kHoldPastFloorMm for the site it is already in: a probe forced through the
  /// floor stays with the site it came down), on the tooth's side of every cut
  /// between shares; of several, the one whose sulcus' middle runs nearest.
  static constexpr double kRadiusMm = 1.2;
  static constexpr double kAboveMarginMm = 0.5;
  static constexpr double kEnterPastFloorMm = 0.5, kHoldPastFloorMm = 3.0;

  /// `sites` must outlive the locator.
  explicit TipLocator(const std::vector<ProbingSite>& sites);

  /// The site whose sulcus holds the tip of the tool at X_WG (its tip is the
  /// tool frame's origin, its axis the frame's z). `held`: the site the tip was
  /// in on the last tick (-1: none).
  TipLocation Locate(const RigidTransform& X_WG, int held = -1) const noexcept;

  /// Whether the tip is within reach of site i's line (its radius and depth
  /// range), whichever site it is assigned to (the report's "nearer another
  /// site's line").
  bool Near(const RigidTransform& X_WG, int i) const noexcept;

  /// The probing force: the push back along the probe's axis (the floor's
  /// answer), not the tissue's sideways push on the shank. Never negative.
  static double ProbingForce(const Vector3& force_W, const RigidTransform& X_WG) noexcept;

  const std::vector<ProbingSite>& sites() const { return sites_; }
  int size() const { return static_cast<int>(sites_.size()); }

 private:
  struct Line {
    Vector3 u;  // unit direction down the sulcus
    double len;
  };
  bool Reach(const Vector3& tip, int i, double past, double* along, double* off) const;
  const std::vector<ProbingSite>& sites_;
  std::vector<Line> lines_;
};

}  // namespace sulcus
