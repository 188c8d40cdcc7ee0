#include "core/anatomy/arch.h"

#include <cmath>
#include <numbers>

namespace sulcus {
namespace {

// Arc length along y = -k x^2 from 0 to x (x >= 0).
double ArcLength(double k, double x) {
  const double u = 2 * k * x;
  return (u * std::sqrt(1 + u * u) + std::asinh(u)) / (4 * k);
}

// The x >= 0 where the arc length from the midline is s (bisection).
double XAtArc(double k, double s) {
  double lo = 0, hi = s;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (ArcLength(k, mid) < s ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Labial/lingual tip of the crown by position (degrees, positive: crown buccal).
double Inclination(int position) {
  static const double deg[8] = {15, 12, 8, 2, 0, -4, -6, -8};
  return deg[position - 1];
}

}  // namespace

Vector3 ArchPoint(bool upper, bool patient_right, double arc, const ArchParams& params) {
  const double k = upper ? params.k_upper : params.k_lower;
  const double x = XAtArc(k, arc);
  return Vector3((patient_right ? -1 : 1) * x,
                 -k * x * x - (upper ? 0 : params.lower_setback_mm),
                 upper ? params.occlusion_mm + params.upper_lift_mm : 0);
}

PlacedTooth PlaceTooth(int fdi, double s_centre, const ArchParams& params) {
  PlacedTooth p;
  p.tooth = FdiTooth::Parse(fdi);
  const bool upper = p.tooth.upper();
  const int pos = p.tooth.position;
  const double k = upper ? params.k_upper : params.k_lower;
  const double sx = (p.tooth.quadrant == 1 || p.tooth.quadrant == 4)
                        ? -1.0
                        : 1.0;  // patient's right: x < 0
  const ToothDimensions d = Dimensions(p.tooth);
  p.contact_mesial_W =
      ArchPoint(upper, sx < 0, std::max(0.0, s_centre - d.md_crown / 2), params);
  p.contact_distal_W = ArchPoint(upper, sx < 0, s_centre + d.md_crown / 2, params);
  const double x = XAtArc(k, s_centre);
  const Vector3 on_arch = ArchPoint(upper, sx < 0, s_centre, params);
  // Mesial: along the arch toward the midline. Buccal: the outward normal, the
  // gradient of y + k x^2 (the arch's inside, the tongue's side, has y < -k x^2).
  p.mesial_W = -Vector3(sx, -2 * k * x, 0).normalized();
  p.buccal_W = Vector3(2 * k * sx * x, 1, 0).normalized();
  p.occlusal_W = upper ? Vector3(-Vector3::UnitZ()) : Vector3(Vector3::UnitZ());
  // The crown tipped buccally (labially) in the occlusal-buccal plane.
  const double tip = Inclination(pos) * std::numbers::pi / 180;
  const Vector3 occlusal = std::cos(tip) * p.occlusal_W + std::sin(tip) * p.buccal_W;
  const Vector3 buccal_t = std::cos(tip) * p.buccal_W - std::sin(tip) * p.occlusal_W;
  // The tooth frame's x: mesial, or distal for mirrored teeth, so that the
  // frame is right-handed.
  p.mirrored = p.mesial_W.cross(buccal_t).dot(occlusal) < 0;
  const Vector3 x_axis = p.mirrored ? Vector3(-p.mesial_W) : p.mesial_W;
  Matrix3 R;
  R.col(0) = x_axis;
  R.col(1) = buccal_t;
  R.col(2) = occlusal;
  R = NearestRotation(R);
  // The contact (height of contour) sits on the arch; the CEJ is below it.
  const double contact_height = (pos <= 3 ? 0.75 : 0.6) * d.crown_height;
  const Vector3 origin = on_arch - contact_height * occlusal;
  p.X_WT = RigidTransform(R, origin);
  return p;
}

double ArchCentreMm(bool upper, int position) {
  // Arc length from the midline to each tooth's centre along its arch (mm),
  // central incisor to third molar, found by FitArchCentres (arch_fit.h) with
  // the exact tooth meshes: each tooth as near its mesial neighbour as it goes
  // without the two meshes intersecting, plus 0.01 mm. A test refits them and
  // checks every pair of teeth with exact triangle geometry.
  static constexpr double kLower[8] = {2.905,  8.632,  15.090, 22.154,
                                       29.193, 38.225, 48.999, 59.266};
  static constexpr double kUpper[8] = {4.793,  12.705, 19.849, 27.153,
                                       33.939, 42.219, 51.743, 60.510};
  return (upper ? kUpper : kLower)[position - 1];
}

std::vector<PlacedTooth> PlaceArch(bool upper, const ArchParams& params) {
  const int last = params.third_molars ? 8 : 7;
  std::vector<PlacedTooth> out;
  for (int side = 0; side < 2; ++side) {  // 0: patient's right (x < 0), 1: left
    const int quadrant = upper ? (side == 0 ? 1 : 2) : (side == 0 ? 4 : 3);
    std::vector<PlacedTooth> half;
    double prev_distal = 0;  // arc length of the previous tooth's distal crown end
    for (int pos = 1; pos <= last; ++pos) {
      const int fdi = 10 * quadrant + pos;
      const double s = ArchCentreMm(upper, pos);
      PlacedTooth p = PlaceTooth(fdi, s, params);
      // The contact with the mesial neighbour: midway between the crowns' ends
      // along the arch, shared by both teeth.
      const double half_width = Dimensions(p.tooth).md_crown / 2;
      if (pos == 1) {
        p.contact_mesial_W =
            ArchPoint(upper, side == 0, 0,
                      params);  // at the midline, shared with the other central
      } else {
        p.contact_mesial_W =
            ArchPoint(upper, side == 0, 0.5 * (prev_distal + s - half_width), params);
        half.back().contact_distal_W = p.contact_mesial_W;
      }
      prev_distal = s + half_width;
      half.push_back(p);
    }
    if (side == 0) {
      out.insert(out.end(), half.rbegin(), half.rend());  // right molars first
    } else {
      out.insert(out.end(), half.begin(), half.end());
    }
  }
  return out;
}

Vector3 ArchMirror(bool mirrored, const Vector3& p) {
  return mirrored ? Vector3(-p.x(), p.y(), p.z()) : p;
}

TriangleMesh ArchMirror(bool mirrored, TriangleMesh mesh) {
  if (mirrored) {
    mesh.Transform(Vector3(-1, 1, 1).asDiagonal(), Vector3::Zero());
    mesh.FlipOrientation();
  }
  return mesh;
}

std::vector<Vector3> ArchMirror(bool mirrored, std::vector<Vector3> points) {
  if (mirrored)
    for (Vector3& p : points) p = ArchMirror(true, p);
  return points;
}

TriangleMesh PlacedMesh(const PlacedTooth& placed, const TriangleMesh& tooth_mesh) {
  TriangleMesh m = ArchMirror(placed.mirrored, tooth_mesh);
  m.Transform(placed.X_WT.rotation(), placed.X_WT.translation());
  return m;
}

}  // namespace sulcus
