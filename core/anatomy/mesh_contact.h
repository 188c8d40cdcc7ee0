#pragma once
// Exact contact between two closed triangle meshes: whether their surfaces
// intersect (exact predicates) and how far apart they are. For placing teeth
// that touch and do not overlap, and for testing that they do. CGAL stays in
// the .cpp file.

#include <vector>

#include "core/geometry/mesh.h"

namespace sulcus {

struct MeshContact {
  bool intersect = false;  // the surfaces cross, or one solid holds the other
  /// Smallest distance from a vertex of either mesh to the other's surface
  /// (0 when they intersect). The true gap is at most this, so "gap <= d" is
  /// never claimed falsely.
  double gap_mm = 0;
};

/// Both meshes closed and outward (TriangleMesh::Check().IsSolid()).
MeshContact MeasureContact(const TriangleMesh& a, const TriangleMesh& b);

/// Just the exact intersection test (quicker than MeasureContact).
bool MeshesIntersect(const TriangleMesh& a, const TriangleMesh& b);

/// The union of two closed, outward meshes as one closed mesh (CGAL's
/// corefinement; exact predicates). Throws std::runtime_error when it cannot
/// be formed (a mesh that intersects itself).
TriangleMesh UniteSolids(const TriangleMesh& a, const TriangleMesh& b);

/// For each point, whether it lies inside (or on) the closed mesh `solid`.
std::vector<bool> InsideSolid(const TriangleMesh& solid,
                              const std::vector<Vector3>& points);

}  // namespace sulcus
