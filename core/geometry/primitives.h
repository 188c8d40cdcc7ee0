#pragma once
// Closed, outward-oriented meshes of simple solids: calibration objects for tests
// and the building blocks of the hard-case scenes (plates, slots, wedges).

#include <utility>
#include <vector>

#include "core/geometry/mesh.h"

namespace sulcus {

/// Axis-aligned box centred at the origin with the given edge lengths (mm).
/// Each face is split into `divisions` x `divisions` quads (two triangles each).
TriangleMesh MakeBox(const Vector3& size, int divisions = 1);

/// Sphere of `radius` from an icosahedron subdivided `subdivisions` times
/// (20 * 4^subdivisions triangles).
TriangleMesh MakeIcosphere(double radius, int subdivisions);

/// Torus about the z axis: ring radius R, tube radius r (r < R); genus 1.
TriangleMesh MakeTorus(double ring_radius, double tube_radius, int ring_segments,
                       int tube_segments);

/// Closed cylinder along z from z = 0 to z = height.
TriangleMesh MakeCylinder(double radius, double height, int segments, int stacks = 1);

/// Tube of circular section swept along a polyline `path` with a radius per path
/// point; the first and last radii should be 0 (the ends close as poles). Closed,
/// manifold and outward when the path bends gently enough that rings do not cross.
TriangleMesh MakeSweep(const std::vector<Vector3>& path, const std::vector<double>& radii,
                       int segments);

}  // namespace sulcus
