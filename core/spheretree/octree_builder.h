#pragma once
// The straightforward reference: an octree over the mesh's bounding cube whose
// spheres circumscribe the cells the surface passes through (the octree method of
// Hubbard and of Bradshaw's toolkit). Every surface point is covered and every
// child lies in its parent, but spheres stick far out of the surface. Kept to
// show, side by side, what the medial builder buys.

#include "core/geometry/mesh.h"
#include "core/spheretree/sphere_tree.h"

namespace sulcus {

/// Octree of `levels` levels (counting the root, so at most 8^(levels-1) leaves).
/// Precondition: the mesh is non-empty.
SphereTree BuildOctreeSphereTree(const TriangleMesh& mesh, int levels);

}  // namespace sulcus
