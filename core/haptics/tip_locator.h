#pragma once
// Where the probe's tip is: the one answer to "which site's sulcus holds the tip,
// how deep along that site's line, at what angle". The probing_depth effect, the
// lesson (its readings, its "you are in the sulcus of"), the window's panel and
// the report all ask this locator; nothing else decides where the tip is.

#include <array>
#include <memory>
#include <vector>

#include "core/geometry/transform.h"
#include "core/geometry/types.h"

namespace sulcus {

/// A tooth's sulcus all the way round, shared by its six sites: per segment
/// (angle 2 pi k / n from the mesial direction toward the facial, in the tooth's
/// frame with the arch's mirror undone) the margin's and the floor's height and
/// the radius of the sulcus' middle; and the six zones that divide it, as
/// clinicians chart: the facial half of the outline (from the mesial contact
/// line round to the distal one) in three equal lengths, MB, B and DB, and the
/// oral half likewise, DL, L and ML. The interdental sites take the
/// interproximal area up to the col's midline (the contact's line), the mid
/// sites the middle thirds.
struct SulcusRing {
  RigidTransform X_RW;  // the world into the ring's frame (before the mirror)
  bool mirrored = false;
  std::vector<double> margin_z, floor_z, sulcus_r;
  std::vector<double> arc_mm;  // along the sulcus' middle from angle 0 to segment k
  double length_mm = 0;        // all the way round
  // Where the zones meet (radians): MB|B, B|DB on the facial half (0..pi),
  // DL|L, L|ML on the oral half (pi..2 pi).
  double facial_from = 0, facial_to = 0, oral_from = 0, oral_to = 0;
  // The cuts between this tooth's share of an arch's gingiva and its
  // neighbours' (a point and the normal toward the neighbour, world).
  std::array<Vector3, 2> cut_q_W{}, cut_n_W{};
  int num_cuts = 0;

  // Per interdental site (MB, DB, ML, DL; the mid sites' unused): the angle
  // where the sulcus meets the neighbour's under the contact (the col's
  // midline): where the ring crosses the cut toward that neighbour, or the
  // contact's line (0 or pi) where there is no cut on that side.
  std::array<double, 6> col_phi{};

  /// Fills the zones' bounds from sulcus_r (thirds of each half's length) and
  /// the col's angles from the cuts (fill the cuts first).
  void MakeZones();
  int size() const { return static_cast<int>(margin_z.size()); }
  /// The segment nearest angle phi (any real angle).
  int SegmentAt(double phi) const;
  /// The site (0..5: MB, B, DB, ML, L, DL) whose zone holds angle phi.
  int ZoneAt(double phi) const;
  /// A world point in the ring's frame, mirrored as the tables are.
  Vector3 ToRing(const Vector3& p_W) const;
  /// The sulcus' middle at angle phi, depth_mm below the margin, in the world
  /// (`outward_mm` further from the tooth's axis).
  Vector3 PointAt(double phi, double depth_mm, double outward_mm = 0) const;
  /// The tooth's long axis in the world (toward the crown).
  Vector3 AxisW() const;
  /// The length along the sulcus' middle from angle phi to the col's midline
  /// of interdental site s (col_phi); 0 past it.
  double ToContactMm(double phi, int site) const;
  /// +1 when site s's zone lies at angles above its col's (a facial mesial or
  /// an oral distal site), -1 otherwise.
  static double TowardZone(int site);
};

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
  // How far round the line was moved from the tooth's line angle to keep it
  // on the tooth's own side of the cut toward its neighbour (degrees; 0:
  // where the gingiva's tables put it).
  double line_moved_deg = 0;
  // The tooth's whole sulcus and its zones (null: the site is its line alone,
  // as in a synthetic test; then the nearest line within kRadiusMm decides).
  std::shared_ptr<const SulcusRing> ring;
};

/// Where the tip is on one tick.
struct TipLocation {
  int site = -1;         // index into the locator's sites; -1: in no site's sulcus
  double depth_mm = 0;   // below the margin along the site's line (negative: above it)
  double off_mm = 0;     // from the site's line
  double angle_deg = 0;  // the probe's axis against the tooth's long axis
  Vector3 tip_W = Vector3::Zero();  // where the tip is
  double phi = 0;  // round the tooth (its ring's angle; 0 without a ring)
  // Interdental sites: along the sulcus to the contact's line (the col's
  // midline); -1 for the mid sites or without a ring.
  double to_contact_mm = -1;
  // In the col: past the cut into the neighbour's gingiva, or past the col's
  // midline; depth_mm is then no deeper than the tooth's own floor there
  // (the floor past it is the neighbour's as much as this tooth's).
  bool past_cut = false;
};

/// The sites' zones, precomputed. Locate() allocates nothing and never throws.
class TipLocator {
 public:
  /// A tip is in a tooth's sulcus when it is within kRadiusMm of the sulcus'
  /// middle (radially, at its angle round the tooth), from kAboveMarginMm above
  /// the margin to kEnterPastFloorMm past the floor there (kHoldPastFloorMm for
  /// the tooth it is already in: a probe forced through the floor stays with
  /// the site it came down), on the tooth's side of every cut between shares;
  /// of several teeth, the one whose sulcus' middle runs nearest (under a
  /// contact the two sulci are one space, the col: a tip of the tooth it was
  /// last in, in that tooth's interproximal area, may be with it past the cut,
  /// up to the contact's line: TipLocation::past_cut). The site is
  /// the zone (SulcusRing) that holds its angle: every point of the sulcus is
  /// in exactly one site. The depth is below the margin at that angle.
  /// Sites without a ring: within kRadiusMm of the site's line, the nearest.
  static constexpr double kRadiusMm = 1.2;
  static constexpr double kAboveMarginMm = 0.5;
  static constexpr double kEnterPastFloorMm = 0.5, kHoldPastFloorMm = 3.0;

  /// `sites` must outlive the locator.
  explicit TipLocator(const std::vector<ProbingSite>& sites);

  /// The site whose sulcus holds the tip of the tool at X_WG (its tip is the
  /// tool frame's origin, its axis the frame's z). `held`: the site the tip was
  /// last in (ProbeReadingTracker::held(); -1: none).
  TipLocation Locate(const RigidTransform& X_WG, int held = -1) const noexcept;

  /// Whether the tip is within reach of site i's line (its radius and depth
  /// range), whichever site it is assigned to (the report's "nearer another
  /// site's line").
  bool Near(const RigidTransform& X_WG, int i) const noexcept;

  /// The one rule for the col: the tip in an interdental site's zone, at
  /// least kColDepthMm below the margin, within reach_mm of the contact's line
  /// along the sulcus (under the contact point). The lesson's score and the
  /// window's panel both ask this.
  static constexpr double kColDepthMm = 1.0;
  static bool UnderContact(const TipLocation& at, double reach_mm) noexcept;

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
  struct Ring {
    const SulcusRing* ring;
    std::array<int, 6> site;  // the locator's index of each zone's site (-1: none)
  };
  bool Reach(const Vector3& tip, int i, double past, double* along, double* off) const;
  bool Cut(const SulcusRing& r, const Vector3& tip) const;
  const std::vector<ProbingSite>& sites_;
  std::vector<Line> lines_;
  std::vector<Ring> rings_;
};

}  // namespace sulcus
