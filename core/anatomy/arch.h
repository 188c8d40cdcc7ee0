#pragma once
// Teeth placed on the dental arches.
//
// World frame W: +x the patient's left, +y anterior (toward the lips), +z up; the
// occlusal plane is z = 0 with the mouth closed. Each arch is the parabola
// y = -k x^2 through the contact points; teeth are laid along it with modest
// inclinations (incisors tipped labially, molars lingually), each as close to
// its mesial neighbour as it goes without the two intersecting (the centres are
// fitted once on the exact meshes, arch_fit.h, and tested).
//
// A tooth's own frame (tooth.h) is right-handed with +x mesial, +y buccal, +z
// occlusal. On the patient's lower left and upper right that triple is
// left-handed in the world, so those teeth are mirrored across their x = 0 plane
// (left and right teeth are mirror images) before being placed by a rotation.

#include <vector>

#include "core/anatomy/tooth.h"
#include "core/geometry/transform.h"

namespace sulcus {

struct ArchParams {
  double k_lower = 0.052;  // parabola y = -k x^2 (1/mm): first molars about 45 mm apart
  double k_upper = 0.045;  // the upper arch is wider and encloses the lower
  double upper_lift_mm =
      0.0;  // raise the upper arch (open the mouth) above its place in occlusion
  double lower_setback_mm = 2.0;  // the lower arch moved back (-y): the incisors' overjet
  // The upper arch's height above the lower when the teeth meet (mouth closed):
  // the least lift at which no upper tooth's mesh intersects a lower one's with
  // the default arches (found by bisection on the exact meshes; a test checks
  // that the teeth are apart here and intersect 0.05 mm lower).
  double occlusion_mm = 4.75;
  bool third_molars = false;  // 28 teeth without them, 32 with
};

struct PlacedTooth {
  FdiTooth tooth;
  bool mirrored = false;                   // mesh mirrored in x before X_WT applies
  RigidTransform X_WT;                     // tooth frame (after the mirror) in the world
  Vector3 mesial_W, buccal_W, occlusal_W;  // unit directions for lesson sites
  Vector3 contact_mesial_W,
      contact_distal_W;  // the arch points where it meets its neighbours
};

/// The point `arc` mm along the arch's occlusal curve from the midline, on the
/// patient's right (x < 0) or left.
Vector3 ArchPoint(bool upper, bool patient_right, double arc,
                  const ArchParams& params = {});

/// Tooth `fdi` on its arch with its crown's centre `s_centre` mm along the arch
/// from the midline (PlaceArch uses the fitted centres, ArchCentreMm).
PlacedTooth PlaceTooth(int fdi, double s_centre, const ArchParams& params = {});

/// Where PlaceArch puts a tooth (1 central incisor .. 8 third molar) along its
/// arch: its crown's centre, mm from the midline along the occlusal curve.
double ArchCentreMm(bool upper, int position);

/// The teeth of one arch (upper or lower), from the right third (or second) molar
/// to the left one, in arch order.
std::vector<PlacedTooth> PlaceArch(bool upper, const ArchParams& params = {});

/// The arch's mirror (x -> -x in the tooth frame), applied when `mirrored`; it is
/// its own inverse. The mesh version also flips the faces so they stay outward.
Vector3 ArchMirror(bool mirrored, const Vector3& p);
TriangleMesh ArchMirror(bool mirrored, TriangleMesh mesh);
/// Points or directions (a mesh's normals), each mirrored alike.
std::vector<Vector3> ArchMirror(bool mirrored, std::vector<Vector3> points);

/// A tooth's mesh in the world: mirrored if needed, then moved by X_WT.
TriangleMesh PlacedMesh(const PlacedTooth& placed, const TriangleMesh& tooth_mesh);

}  // namespace sulcus
