#pragma once
// Procedural teeth from clinical dimensions (typical adult values from dental anatomy
// texts), by FDI number.
//
// Tooth frame (every tooth, upper or lower): origin at the centre of the
// cemento-enamel junction (CEJ) level, +z along the long axis toward the
// occlusal/incisal end, +x mesial, +y buccal (labial). Placing a tooth in an arch
// (upper teeth are turned over) is the arch's job.
//
// The solid is implicit: a crown-neck-root profile of superelliptic cross-sections
// by height, cut by an occlusal height field with the tooth type's cusps, joined
// smoothly to tapered root cones below a furcation for multi-rooted teeth. It is
// meshed by projecting a subdivided icosahedron radially from a point inside the
// crown onto that surface, so the mesh is closed, manifold, outward-oriented and
// free of self-intersections by construction, with the same vertex count for every
// tooth (10 * 4^resolution + 2).

#include <algorithm>
#include <string>
#include <vector>

#include "core/geometry/mesh.h"

namespace sulcus {

enum class ToothType {
  kCentralIncisor,
  kLateralIncisor,
  kCanine,
  kFirstPremolar,
  kSecondPremolar,
  kFirstMolar,
  kSecondMolar,
  kThirdMolar
};

/// Typical adult dimensions, mm (dental anatomy texts' typical values; third molars from
/// second molars, slightly smaller).
struct ToothDimensions {
  double crown_height = 0;
  double root_length = 0;  // the buccal roots of multi-rooted upper teeth
  double md_crown = 0;     // mesiodistal width at the contact areas
  double md_cervix = 0;    // mesiodistal width at the CEJ
  double bl = 0;           // bucco-lingual width of the crown
  int roots = 1;
  double palatal_root_length =
      0;  // upper molars' palatal root when longer (0: as root_length)
  /// The deepest any root reaches below the CEJ.
  double longest_root() const { return std::max(root_length, palatal_root_length); }
};

/// What a valid FDI number names. Throws std::invalid_argument with a message
/// ("FDI 19 does not exist: the tooth digit is 1 to 8") for anything else;
/// quadrants 1 to 4 (permanent teeth) only.
struct FdiTooth {
  int fdi = 0;
  int quadrant = 0;  // 1 upper right, 2 upper left, 3 lower left, 4 lower right
  int position = 0;  // 1 central incisor .. 8 third molar
  bool upper() const { return quadrant <= 2; }
  ToothType type() const { return static_cast<ToothType>(position - 1); }
  static FdiTooth Parse(int fdi);
  /// Whether Parse accepts `fdi` (for code that must not throw on a number a
  /// reader has already reported).
  static bool Valid(int fdi) {
    return fdi / 10 >= 1 && fdi / 10 <= 4 && fdi % 10 >= 1 && fdi % 10 <= 8;
  }
};

std::string ToString(ToothType type);
ToothDimensions Dimensions(const FdiTooth& tooth);

/// Changes whenever GenerateTooth's meshes change: caches of generated meshes
/// (teeth, and the gingiva and calculus shaped around them) key on it.
inline constexpr int kToothShapeVersion = 5;

struct ToothParams {
  int resolution = 4;  // icosahedron subdivisions: 4 gives 5,120 triangles (the paper's
                       // ~4,000), 5 gives 20,480
};

struct ToothModel {
  FdiTooth tooth;
  ToothDimensions dimensions;
  TriangleMesh mesh;         // in the tooth frame
  std::vector<Vector3> cej;  // the CEJ as a closed curve on the surface (72 points)
  Vector3 long_axis = Vector3::UnitZ();
  std::vector<Vector3> root_tops;  // multi-rooted teeth: where each root's axis starts,
                                   // under the furcation
};

/// Generates a tooth. Deterministic: the same number and parameters give the same
/// mesh, bit for bit.
ToothModel GenerateTooth(int fdi, const ToothParams& params = {});

}  // namespace sulcus
