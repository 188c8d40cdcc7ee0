#pragma once
// A closed surface from a scalar field: the zero set of f (f < 0 inside),
// sampled on a regular grid and cut into tetrahedra.
//
// Each grid cube is split into the six tetrahedra that run from its lowest
// corner to its highest (the Kuhn split). Neighbouring cubes split their shared
// faces along the same diagonal, so the pieces join into one closed,
// edge-manifold surface; a tetrahedron holds at most two triangles, which makes
// no case table and no ambiguous case. Grid values at or near zero are pushed
// outward by a small fraction of a cell, so that no crossing falls on a grid
// point and no triangle is degenerate.

#include <functional>

#include "core/geometry/mesh.h"

namespace sulcus {

/// The surface f = 0 inside `box`, with faces outward (toward f > 0). Where
/// the inside reaches the box the surface is closed along it. Throws
/// std::invalid_argument for a cell that is not positive or a grid of more than
/// 2^24 points.
TriangleMesh Isosurface(const std::function<double(const Vector3&)>& f, const Aabb& box,
                        double cell_mm);

}  // namespace sulcus
