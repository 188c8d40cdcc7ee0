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
// The planes cost nothing per node test, and a few distances per leaf pair
// within 0.1 mm of the tool.

#include <array>
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
  /// Leaves with at least one plane.
  int count() const;
};

struct LeafPlaneParams {
  /// Faces whose normals are within this angle of a plane's normal share that
  /// plane; a leaf whose faces need more than kMaxPlanes such groups gets the
  /// kMaxPlanes largest (any normal gives a conservative plane; these are the
  /// tight ones).
  double group_angle_deg = 60.0;
};

/// Fits each leaf's planes to the mesh's faces inside its sphere: the faces are
/// grouped by normal, each group's area-weighted mean normal is a plane's, and
/// its offset is the largest n.p over the part of every face (of every group)
/// inside the sphere, computed exactly (vertices inside, edge crossings of the
/// sphere, and the extreme of the face's disc of intersection). The tree
/// must bound the mesh (every face inside the union of its leaves) and each
/// node's sphere must contain its children's.
LeafPlanes FitLeafPlanes(const TriangleMesh& mesh, const SphereTree& tree,
                         const LeafPlaneParams& params = {});

}  // namespace sulcus
