#pragma once
// The gingiva around one tooth, with the clinical truth of its six probing sites.
//
// A collar of soft tissue in the tooth's frame (tooth.h): its top edge is the
// gingival margin (1.5 mm above the CEJ by default, lowered by recession, raised
// into papillae between teeth); inside it, a sulcus separates it from the tooth,
// whose floor (the attachment) lies `pocket` millimetres below the margin. Pocket
// depth and recession are given at the six sites (MB, B, DB, ML, L, DL) and
// interpolated smoothly around the tooth. The sulcus is geometrically
// exaggerated: its wall is vertical at the tooth's widest point plus `gap_mm`, so
// a 0.5 mm probe tip enters at every site and reaches the floor straight down.
// Soft-tissue behaviour (displacing the gingiva) is an effect, not geometry.

#include <array>
#include <cstdint>
#include <numbers>
#include <vector>

#include "core/anatomy/mesh_clip.h"
#include "core/anatomy/tooth.h"

namespace sulcus {

/// The six sites' lines in the tooth frame as a lone tooth has them, radians
/// from +x (mesial) toward +y (buccal), in charting order (MB, B, DB, ML, L,
/// DL): the mid sites square to the arch, the others at 45 degrees from them.
inline constexpr std::array<double, 6> kSiteAngles = {
    std::numbers::pi / 4,     std::numbers::pi / 2,     3 * std::numbers::pi / 4,
    7 * std::numbers::pi / 4, 3 * std::numbers::pi / 2, 5 * std::numbers::pi / 4};

struct GingivaParams {
  std::array<double, 6> pocket_mm{2, 2, 2, 2, 2, 2};  // MB, B, DB, ML, L, DL
  std::array<double, 6> recession_mm{};  // positive: the margin moves toward the root
  double margin_above_cej_mm = 1.5;
  double gap_mm = 0.85;  // sulcus width at its narrowest: a 0.5 mm tip fits with room for
                         // the sphere-trees
  double thickness_mm = 0;  // buccal and lingual, thinner between teeth; 0: the tooth's
                            // own (GingivaThicknessMm)
  double papilla_mm = 1.5;  // how far the margin rises between teeth
  // Each site's line (kSiteAngles unless the arch crowds an interdental line
  // past the cut toward the neighbour: LineAnglesClearOfCuts moves it round
  // toward its mid site). The pocket's depth and the recession take their
  // knots at these angles, so each site's depth is the deepest of its zone
  // where its line is.
  std::array<double, 6> site_angle = kSiteAngles;
  int segments = 72;  // around the tooth (a multiple of 8 puts a ring at every site)
  // A share of the arch's gingiva (not a collar) covers the alveolar process
  // down to the bone crest, `crest_drop_mm` below the CEJ's centre along the
  // world's vertical (`crest_up`: toward the crown, in the tooth frame), and
  // 1 mm past it into the jaw, narrowing there so that it ends inside the
  // jaw. 0: the share ends 1 mm below the floor, as a collar does.
  double crest_drop_mm = 0;
  Vector3 crest_up = Vector3::UnitZ();
};

struct GingivaModel {
  TriangleMesh mesh;                   // in the tooth frame
  std::array<double, 6> site_angle{};  // radians from +x (mesial) toward +y (buccal)
  std::array<Vector3, 6> margin{};     // each site on the margin, in the sulcus' middle
  std::array<Vector3, 6> floor{};      // the pocket floor below it
  // Per segment around the tooth (angle 2 pi k / segments): the floor height,
  // the margin height and the radius of the sulcus' middle (where a probe tip
  // walks; lessons measure coverage of the walking stroke with them).
  std::vector<double> floor_z, margin_z, sulcus_r;
  // Per segment too: the sulcus wall's radius, where the floor meets the root
  // (inside it, so the attachment overlaps the tooth) and the outer surface.
  std::vector<double> wall_r, floor_r, outer_r;
  // The bone crest for a share (GingivaParams::crest_drop_mm; 0: none): the
  // plane of points q with q . crest_up = -crest_drop_mm.
  double crest_drop_mm = 0;
  Vector3 crest_up = Vector3::UnitZ();
  // For drawing, a share's only (empty for a collar): per vertex of `mesh`, the
  // unit normal of the gingiva's surface there, the gradient of the share's
  // uncut field; zero where the field gives none. Two neighbouring shares
  // take the same normal where their rims meet, so the seam does not show in
  // the shading, nor the facets of the sampling.
  std::vector<Vector3> normals;
  // A share's only, too: per face of `mesh`, 1 for a face of its flat cap on
  // a cut toward a neighbour (where two shares meet face to face), else 0.
  std::vector<char> caps;
  /// The floor height at angle th (radians from +x), nearest segment.
  double FloorAt(double th) const;
  /// The segment of the tables around the tooth nearest angle th (radians from +x).
  int SegmentAt(double th) const;
};

/// Changes whenever the share's geometry does (its meshes are cached by it).
inline constexpr int kGingivaShareVersion = 41;

/// A neighbouring tooth on the arch, for the gingiva between the two.
struct GingivaNeighbour {
  const ToothModel* tooth = nullptr;
  const GingivaModel* gingiva =
      nullptr;  // its collar's model (its tables; the mesh is not used)
  Matrix3 A =
      Matrix3::Identity();      // this tooth's frame to the neighbour's: p_n = A p + b
  Vector3 b = Vector3::Zero();  // (A may hold the arch's mirror)
};

/// Which surface of the gingiva a share is: the one the probe feels, with the
/// sulcus opened `gap_mm` wide around the tooth down to the pocket floor (a
/// vertical wall, so that a 0.5 mm tip enters at every site; the engine's
/// geometry and every site measurement), or the one the eye sees: the same
/// tissue closed round the tooth, its inner wall following the tooth's surface
/// at every height (a real sulcus is a crevice that the probe
/// opens by pushing the gingiva aside), so that the papillae fill the
/// embrasures under the contacts instead of standing as two thin shells over a
/// hollow col; and its free gingiva thin at the margin (about 0.45 mm outside
/// the tooth), thickening downward to the felt face at the bone crest, where
/// the jaw's mucosa meets it. Only drawn, never felt: the window draws the
/// seen surface and the engine works on the felt one.
enum class GingivaSurface { kFelt, kSeen };

/// Where the seen gingiva's inner wall lies, outward from the tooth's surface
/// (mm): a little inside the tooth, so that the tooth hides it and the margin
/// meets the tooth in one clean line (sampled on a 0.3 mm grid, a wall drawn
/// just outside the tooth would dip in and out of it, in patches that show
/// through translucent gingiva).
inline constexpr double kSeenWallMm = -0.2;

/// Changes whenever the seen gingiva's geometry does and the felt one's does
/// not (its meshes are cached by both).
inline constexpr int kSeenGingivaVersion = 9;

/// A tooth's outer surface as a table, in its frame: for each of 144 angles
/// around the axis and each height 0.1 mm apart, the farthest crossing of the
/// horizontal ray from the axis with the mesh (OuterRadius, for all of them at
/// once: one pass over the faces).
class ToothRadii {
 public:
  ToothRadii(const TriangleMesh& mesh, double z_lo, double z_hi);
  /// Bilinear in angle and height; 0 outside the heights. Where a ray misses
  /// the tooth (between a molar's roots) the radius runs straight around from
  /// the root before to the root after.
  double At(double th, double z) const;

 private:
  static constexpr int kAngles = 144;
  static constexpr double kDz = 0.1;
  double z0_;
  int levels_;
  std::vector<float> r_;  // [level * kAngles + angle]
};

/// The field of a tooth's share of the gingiva (negative inside), in the
/// tooth's frame. `Uncut` is the gingiva before the cuts toward the
/// neighbours: two neighbours' shares compute the same value at the same point
/// of their cut. `Cut` is the signed distance past the nearest cut plane
/// (positive on a neighbour's side). GenerateGingiva samples `Uncut` and clips
/// the surface exactly at the `cuts()`. Holds pointers to its arguments, which
/// must outlive it.
class GingivaShareField {
 public:
  GingivaShareField(const ToothModel& tooth, const GingivaModel& own,
                    const std::vector<GingivaNeighbour>& neighbours,
                    GingivaSurface surface = GingivaSurface::kFelt);
  // (not copied: the seen field's links point into its own table of radii)
  GingivaShareField(const GingivaShareField&) = delete;
  GingivaShareField& operator=(const GingivaShareField&) = delete;
  double Uncut(const Vector3& p) const;
  double Cut(const Vector3& p) const;
  const Aabb& box() const { return box_; }
  /// The cut toward each neighbour, in this tooth's frame: a point q on it and
  /// its unit normal toward the neighbour (the same plane from both sides); a
  /// ClipPlane, as the share's mesh is clipped at it.
  using CutPlane = ClipPlane;
  std::vector<CutPlane> cuts() const;
  // A site this close to a cut lies under the contact: the margin beside it
  // is the papilla's, which rises above the site's own.
  static constexpr double kUnderContactMm = 0.6;

 private:
  struct Link {
    const GingivaNeighbour* n;
    Eigen::Vector2d e;  // toward the neighbour's axis, horizontal here
    double L;           // to its axis
    Vector3 q, normal;  // the cut: through q, normal toward the neighbour (the same plane
                        // from both sides)
    Vector3 face_point[2],
        face_normal[2];     // the interdental band's buccal and lingual faces
    double face_th[2][2];   // each face's side: its angle around this tooth [0] and the
                            // neighbour [1]
    Vector3 wall_point[2];  // the same faces through the two sulci's walls: the papilla's
                            // tip stays within them
    Vector3 across_dir;     // in the cut, square to the mean vertical
    Vector3 up;             // the two teeth's mean vertical
    Vector3 papilla;        // the papilla's top, by the contact
    double slope[2];        // its fall per mm from the cut toward this tooth [0] and the
                            // neighbour [1]
    Vector3 base;           // the interdental gingiva's base
    // The bone crest at this tooth's axis and at the neighbour's, heights
    // along the world's vertical (crest_up; -inf: no attached gingiva); between
    // the two it runs straight, as the jaw's does.
    double crest_own, crest_other;
    // How far each tooth's interproximal site facing the other lies from the
    // cut, [0] with across_dir, [1] against it: the col reaches the deeper
    // tooth's floor there.
    double own_site_gap[2], other_site_gap[2];
    const ToothRadii* seen =
        nullptr;  // the neighbour's surface, for the seen gingiva (null: felt)
  };
  const GingivaModel* own_;
  std::vector<ToothRadii>
      radii_;  // for the seen gingiva: this tooth's, then each neighbour's
  const ToothRadii* seen_ = nullptr;  // this tooth's (null: felt)
  std::vector<Link> links_;
  Aabb box_;
};

/// How thick a tooth's gingiva is buccally and lingually over its cervix by
/// default (mm): 1.0 over the incisors, 1.2 over the canines, 1.5 over the
/// premolars and molars (a thin phenotype at the front of the mouth, thicker
/// further back).
double GingivaThicknessMm(const FdiTooth& tooth);

/// The most attachment a site can lose (pocket plus recession, mm) and keep at
/// least 1 mm of root in the gingiva.
inline double MaxAttachmentLoss(const ToothDimensions& d) {
  return d.longest_root() - 1.0;
}

/// The farthest crossing of the horizontal ray from (0, 0, z) along angle th
/// (radians from +x) with the mesh: the tooth's outer surface in that
/// direction at that height, or 0 when the ray misses.
double OuterRadius(const TriangleMesh& mesh, double th, double z);

/// OuterRadius for many rays at one mesh: its faces sorted into 0.1 mm bands
/// of height, so that a ray tests only the faces that reach its height (the
/// same answers, each face's test computed as OuterRadius computes it).
/// Holds a reference to the mesh, which must outlive it.
class OuterRadii {
 public:
  explicit OuterRadii(const TriangleMesh& mesh);
  double At(double th, double z) const;

 private:
  static constexpr double kBandMm = 0.1;
  const TriangleMesh& mesh_;
  double z0_ = 0;
  int bands_ = 0;
  std::vector<std::int32_t> start_, faces_;  // band b: faces_[start_[b] .. start_[b+1])
};

/// Site angles in the tooth frame, in charting order (MB, B, DB, ML, L, DL),
/// as a lone tooth has them (kSiteAngles).
const std::array<double, 6>& SiteAngles();

/// The plane a share of the arch's gingiva is cut at toward a neighbour
/// (`next`, its frame p_n = A p + b): halfway between the two teeth's contact
/// points, its normal halfway between the two horizontal directions, pointing
/// toward the neighbour. Both shares compute the same plane.
ClipPlane CutToward(const ToothModel& tooth, const ToothModel& next, const Matrix3& A,
                    const Vector3& b);

/// How far the sulcus' middle at an interdental line must stay on the tooth's
/// own side of each cut (mm).
inline constexpr double kLineClearOfCutMm = 0.3;

/// The six lines of `params` (starting from params.site_angle), each
/// interdental line moved round toward its mid site, half a degree at a time
/// and at most 30 degrees, until the sulcus' middle halfway down the pocket
/// there is kLineClearOfCutMm on the tooth's own side of every cut (in a
/// crowded or curved arch a 45-degree line angle can lie in the neighbour's
/// gingiva, where the neighbour's sulcus is). Checked again on the collar the
/// moved lines make, until it holds. The one rule for where a line lies: the
/// scene links it into every share's parameters.
std::array<double, 6> LineAnglesClearOfCuts(const ToothModel& tooth,
                                            const GingivaParams& params,
                                            const std::vector<ClipPlane>& cuts);

/// The collar around `tooth`. Throws std::invalid_argument for a pocket deeper
/// than the root or a bad parameter.
GingivaModel GenerateGingiva(const ToothModel& tooth, const GingivaParams& params = {});

/// The tooth's share of its arch's gingiva: the collar above, joined to its
/// neighbours' by the interdental gingiva (a papilla buccal and lingual of each
/// contact, rising toward it), and cut at the plane halfway between the two
/// teeth's contact surfaces, so that the shares of an arch meet face to face
/// and make one gingiva. The sulci of both teeth are kept open: under a
/// contact they meet, and the tissue beneath them (the col) is the floor, so a
/// probe walks around a tooth and under its contacts. The site truth (margin,
/// floor, tables) is the collar's; only the mesh differs. Sampled as the zero
/// set of a field on a grid of `cell_mm` (isosurface.h), then clipped at the
/// cut planes with flat caps (mesh_clip.h). With no neighbours it is the collar.
/// `surface`: the felt gingiva, or the seen one (GingivaSurface; its tables
/// and sites are the felt one's, only the mesh and normals differ).
GingivaModel GenerateGingiva(const ToothModel& tooth, const GingivaParams& params,
                             const std::vector<GingivaNeighbour>& neighbours,
                             double cell_mm = 0.3,
                             GingivaSurface surface = GingivaSurface::kFelt);

}  // namespace sulcus
