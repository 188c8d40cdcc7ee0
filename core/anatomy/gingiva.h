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

#include "core/anatomy/tooth.h"

namespace sulcus {

struct GingivaParams {
  std::array<double, 6> pocket_mm{2, 2, 2, 2, 2, 2};   // MB, B, DB, ML, L, DL
  std::array<double, 6> recession_mm{};               // positive: the margin moves toward the root
  double margin_above_cej_mm = 1.5;
  double gap_mm = 1.0;           // sulcus width at its narrowest: a 0.5 mm tip fits with room for the sphere-trees
  double thickness_mm = 2.0;     // buccal and lingual; thinner between teeth
  double papilla_mm = 1.5;       // how far the margin rises between teeth
  int segments = 72;             // around the tooth (a multiple of 8 puts a ring at every site)
};

struct GingivaModel {
  TriangleMesh mesh;                    // in the tooth frame
  std::array<double, 6> site_angle{};   // radians from +x (mesial) toward +y (buccal)
  std::array<Vector3, 6> margin{};      // each site on the margin, in the sulcus' middle
  std::array<Vector3, 6> floor{};       // the pocket floor below it
  // Per segment around the tooth (angle 2 pi k / segments): the floor height,
  // the margin height and the radius of the sulcus' middle (where a probe tip
  // walks; lessons measure coverage of the walking stroke with them).
  std::vector<double> floor_z, margin_z, sulcus_r;
  /// The floor height at angle th (radians from +x), nearest segment.
  double FloorAt(double th) const;
};

/// The most attachment a site can lose (pocket plus recession, mm) and keep at
/// least 1 mm of root in the gingiva.
inline double MaxAttachmentLoss(const ToothDimensions& d) { return d.longest_root() - 1.0; }

/// The farthest crossing of the horizontal ray from (0, 0, z) along angle th
/// (radians from +x) with the mesh: the tooth's outer surface in that
/// direction at that height, or 0 when the ray misses.
double OuterRadius(const TriangleMesh& mesh, double th, double z);

/// Site angles in the tooth frame, in charting order (MB, B, DB, ML, L, DL).
const std::array<double, 6>& SiteAngles();

/// The collar around `tooth`. Throws std::invalid_argument for a pocket deeper
/// than the root or a bad parameter.
GingivaModel GenerateGingiva(const ToothModel& tooth, const GingivaParams& params = {});

}  // namespace sulcus
