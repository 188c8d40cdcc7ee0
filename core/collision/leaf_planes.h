#pragma once
// Leaf spheres clipped by planes: the surface a sliding tool feels.
//
// A sphere-tree leaf bulges out of a flat face by up to its protrusion, and a
// tool sliding over a face covered by many leaves rides over the bumps between
// them (the force ripple of the paper's sphere approximation). Each leaf can
// also carry up to kMaxPlanes planes n.x = d with every point of the object's
// surface inside the leaf sphere on or below each of them (n.p <= d). The leaf
// is then the sphere cut by those planes (CollisionWorld::LeafGap measures a
// tool sphere's distance to it), still conservative, and on a flat face every
// leaf's plane is the face itself, so a tool slides on the true face with no
// bumps at all. A leaf centred in a slab (the builder covers volume) is cut by
// both faces; one across an edge by both faces of the edge; on a curved
// surface the plane is a facet much closer to it than the sphere's cap.
//
// In a concave crease (a V groove, a fissure, the corner where a floor meets a
// wall) that intersection cannot follow the surface: each face rises above the
// other's plane inside the sphere, so each plane must be lifted over the other
// face, and the tool is held off the crease by up to the lift. There the leaf is
// instead cut by the union of the crease's planes' half spaces, each of them
// bounding only the faces of its own group (and of the groups cut as before):
// every point of the surface inside the sphere is below one of them, and the
// region above them all is the free space over the crease. Any other plane of
// the leaf (a bottom face a large leaf reaches) still cuts it as before.
//
// The planes cost nothing per node test, and a few distances per leaf pair
// within 0.1 mm of the tool.

#include <array>
#include <cstdint>
#include <vector>

#include "core/geometry/mesh.h"
#include "core/spheretree/sphere_tree.h"

namespace sulcus {

/// Per node of a tree, in the tree's frame: the clipping planes of a leaf
/// (unused ones: n zero, d kNone, so that their gap is far below any sphere gap).
struct LeafPlanes {
  static constexpr int kMaxPlanes = 3;
  static constexpr double kNone = 1e30;
  std::vector<std::array<Vector3, kMaxPlanes>> n;
  std::vector<std::array<double, kMaxPlanes>> d;
  /// Per node: the planes (bit j for plane j) whose half spaces are united (a
  /// concave crease, two or three of them); the leaf is the sphere cut by each
  /// other plane and by that union. 0: by the intersection of every plane.
  std::vector<std::uint8_t> concave;
  /// Leaves with at least one plane.
  int count() const;
  /// Whether the point p (tree frame) is in leaf n's clipped part of space
  /// (below its planes as `concave` combines them; every point when it has none).
  bool Below(std::size_t n, const Vector3& p, double tolerance) const;
};

struct LeafPlaneParams {
  /// Faces whose normals are within this angle of a plane's normal share that
  /// plane; a leaf whose faces need more than kMaxPlanes such groups gets the
  /// kMaxPlanes largest (any normal gives a conservative plane; these are the
  /// tight ones).
  double group_angle_deg = 60.0;
  /// Groups of faces each rising above the others' planes form a concave
  /// crease, cut by the union of their planes, when that lowers the planes by
  /// more than this in all (mm; 0 or less: never).
  double concave_lift_mm = 0.005;
};

/// Fits each leaf's planes to the mesh's faces inside its sphere: the faces are
/// grouped by normal, each group's area-weighted mean normal is a plane's, and
/// its offset is the largest n.p over the part of every face (of every group;
/// of its own group in a concave crease) inside the sphere, computed exactly (vertices
/// inside, edge crossings of the sphere, and the extreme of the face's disc of
/// intersection). The tree must bound the mesh (every face inside the union of its
/// leaves) and each node's sphere must contain its children's.
LeafPlanes FitLeafPlanes(const TriangleMesh& mesh, const SphereTree& tree,
                         const LeafPlaneParams& params = {});

}  // namespace sulcus
