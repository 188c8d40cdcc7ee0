#pragma once
// Mesh simplification by edge collapse.

#include "core/geometry/mesh.h"

namespace sulcus {

/// The mesh with fewer faces: edges collapsed while the squared distances of
/// each moved vertex to the planes of the faces it came from, each weighted by
/// its face's area in mm^2 and summed (the quadric error), stay under
/// `max_error_mm`^2; no face turns by more than 30 degrees and no face becomes
/// a sliver (longest edge over its height above 8) where there was none. Each
/// collapse moves a vertex onto a neighbour, so every vertex left is one of the
/// input's (an isosurface's stay on the level set). A closed mesh stays closed,
/// a border stays as it is. Meant for isosurfaces, whose flat parts carry many
/// small faces.
TriangleMesh Simplify(const TriangleMesh& mesh, double max_error_mm);

/// The same rules applied by OpenMesh's decimater (its quadric, normal
/// flipping and aspect ratio modules): the reference Simplify is measured
/// against (tests and `sulcus-cli mesh simplify --compare`), four to six times
/// slower, and what the felt gingiva is simplified with (its meshes and trees
/// stay as every reading was measured on them). The decimater asks the mesh
/// whether each collapse keeps its topology; Sulcus answers with the same
/// test as OpenMesh, without the allocations of the library's own answer
/// (`library_collapse_check`: the library's, slower, for the test that keeps
/// the two the same).
TriangleMesh SimplifyWithOpenMesh(const TriangleMesh& mesh, double max_error_mm,
                                  bool library_collapse_check = false);

}  // namespace sulcus
