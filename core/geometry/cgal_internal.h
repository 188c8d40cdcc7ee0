#pragma once
// CGAL's kernel and surface mesh for the .cpp files of modules that link CGAL
// (the sphere-tree builder, the mesh oracle, mesh contact and clipping). Private:
// never include it from a header, so that CGAL stays out of every interface.

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

#include <vector>

#include "core/geometry/mesh.h"

namespace sulcus {

using CgalKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalPoint = CgalKernel::Point_3;
using CgalMesh = CGAL::Surface_mesh<CgalPoint>;

inline CgalPoint ToCgal(const Vector3& v) { return CgalPoint(v.x(), v.y(), v.z()); }

/// The mesh as a CGAL surface mesh, vertex for vertex and face for face. Faces
/// Surface_mesh refuses (non-manifold) are dropped: callers validate first.
inline CgalMesh ToCgalMesh(const TriangleMesh& input) {
  CgalMesh m;
  std::vector<CgalMesh::Vertex_index> vi;
  vi.reserve(input.num_vertices());
  for (const Vector3& v : input.vertices()) vi.push_back(m.add_vertex(ToCgal(v)));
  for (const auto& f : input.faces()) m.add_face(vi[f[0]], vi[f[1]], vi[f[2]]);
  return m;
}

}  // namespace sulcus
