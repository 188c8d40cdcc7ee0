#include "core/anatomy/mesh_clip.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/clip.h>
#include <CGAL/Surface_mesh.h>

#include <stdexcept>
#include <unordered_map>

namespace sulcus {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

}  // namespace

TriangleMesh ClipByPlanes(const TriangleMesh& solid, const std::vector<ClipPlane>& planes) {
  if (planes.empty()) return solid;
  Mesh m;
  {
    std::vector<Mesh::Vertex_index> vi;
    vi.reserve(solid.num_vertices());
    for (const Vector3& v : solid.vertices()) vi.push_back(m.add_vertex(Point(v.x(), v.y(), v.z())));
    for (const auto& f : solid.faces())
      if (m.add_face(vi[f[0]], vi[f[1]], vi[f[2]]) == Mesh::null_face())
        throw std::invalid_argument("clip: the mesh is not a manifold surface");
  }
  if (!CGAL::is_closed(m)) throw std::invalid_argument("clip: the mesh is not closed");
  for (const ClipPlane& p : planes) {
    // CGAL keeps the plane's negative side: a x + b y + c z + d < 0.
    const K::Plane_3 plane(p.normal.x(), p.normal.y(), p.normal.z(), -p.normal.dot(p.q));
    if (!PMP::clip(m, plane, CGAL::parameters::clip_volume(true)))
      throw std::invalid_argument("clip: the mesh intersects itself, so its cut cannot be closed");
  }
  std::vector<Vector3> vertices;
  std::vector<TriangleMesh::Face> faces;
  std::unordered_map<Mesh::Vertex_index, std::int32_t> index;
  for (const Mesh::Vertex_index v : m.vertices()) {
    index.emplace(v, static_cast<std::int32_t>(vertices.size()));
    const Point& p = m.point(v);
    vertices.emplace_back(p.x(), p.y(), p.z());
  }
  for (const Mesh::Face_index f : m.faces()) {
    TriangleMesh::Face face{};
    int k = 0;
    for (const Mesh::Vertex_index v : CGAL::vertices_around_face(m.halfedge(f), m)) {
      if (k == 3) throw std::logic_error("clip: a face that is not a triangle");
      face[k++] = index.at(v);
    }
    faces.push_back(face);
  }
  return TriangleMesh(std::move(vertices), std::move(faces));
}

}  // namespace sulcus
