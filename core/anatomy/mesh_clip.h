#pragma once
// Cutting a closed triangle mesh by planes, exactly: what lies past a plane is
// removed and the cut is closed with a flat cap, so the result is closed too.
// For meshes sampled on a grid whose true edge is a plane (a share of the
// gingiva ends at the plane halfway between two teeth): a sharp edge sampled
// on a grid aliases into a saw-tooth, a clipped one does not. Linear in the
// mesh's size, plus the caps' triangulation. CGAL stays in the .cpp file.

#include <vector>

#include "core/geometry/mesh.h"

namespace sulcus {

/// A plane through `q` with unit normal `normal`; its keep side is where
/// (p - q) . normal < 0.
struct ClipPlane {
  Vector3 q, normal;
};

/// The part of the closed, outward mesh `solid` on the keep side of every
/// plane, closed by flat caps on the planes: each face crossing a plane is
/// cut at it (the new vertices exactly on it), and the cut's outlines are
/// filled by a constrained Delaunay triangulation (CGAL, exact predicates),
/// holes left open. A vertex within a millionth of a millimetre of a plane
/// counts as kept. Throws std::invalid_argument when the mesh is not a closed
/// manifold or its cut's outline crosses itself (the mesh intersects itself).
TriangleMesh ClipByPlanes(const TriangleMesh& solid,
                          const std::vector<ClipPlane>& planes);

}  // namespace sulcus
