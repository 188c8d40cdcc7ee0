#pragma once
// Mesh simplification by edge collapse (OpenMesh's decimater, kept out of
// headers).

#include "core/geometry/mesh.h"

namespace sulcus {

/// The mesh with fewer faces: edges collapsed while every moved vertex stays
/// within `max_error_mm` of the planes of the faces it came from (quadric
/// error), no face flips and no face becomes a sliver. A closed mesh stays
/// closed. Meant for isosurfaces, whose flat parts carry many small faces.
TriangleMesh Simplify(const TriangleMesh& mesh, double max_error_mm);

}  // namespace sulcus
