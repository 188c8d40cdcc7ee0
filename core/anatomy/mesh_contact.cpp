#include "core/anatomy/mesh_contact.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/intersection.h>
#include <CGAL/Side_of_triangle_mesh.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <unordered_map>
#include <vector>

#include "core/geometry/cgal_internal.h"

namespace sulcus {
namespace {

using K = CgalKernel;
using Point = CgalPoint;
using Mesh = CgalMesh;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
namespace PMP = CGAL::Polygon_mesh_processing;

bool BoxesApart(const TriangleMesh& a, const TriangleMesh& b, double margin) {
  const Aabb x = a.Bounds(), y = b.Bounds();
  for (int i = 0; i < 3; ++i)
    if (x.min[i] > y.max[i] + margin || y.min[i] > x.max[i] + margin) return true;
  return false;
}

// Smallest distance from a vertex of `from` to the surface in `tree`.
double VertexGap(const TriangleMesh& from, const Tree& tree) {
  double best = std::numeric_limits<double>::infinity();
  for (const Vector3& v : from.vertices())
    best = std::min(best, tree.squared_distance(Point(v.x(), v.y(), v.z())));
  return std::sqrt(best);
}

}  // namespace

TriangleMesh UniteSolids(const TriangleMesh& a, const TriangleMesh& b) {
  Mesh ma = ToCgalMesh(a), mb = ToCgalMesh(b), out;
  if (!PMP::corefine_and_compute_union(ma, mb, out))
    throw std::runtime_error("the union of two meshes could not be formed");
  std::vector<Vector3> v;
  std::unordered_map<std::uint32_t, int> index;
  for (const Mesh::Vertex_index i : out.vertices()) {
    const Point& p = out.point(i);
    index[static_cast<std::uint32_t>(i)] = static_cast<int>(v.size());
    v.emplace_back(p.x(), p.y(), p.z());
  }
  std::vector<TriangleMesh::Face> f;
  for (const Mesh::Face_index fi : out.faces()) {
    TriangleMesh::Face face{};
    int k = 0;
    for (const Mesh::Vertex_index vi :
         CGAL::vertices_around_face(out.halfedge(fi), out)) {
      if (k < 3) face[k] = index.at(static_cast<std::uint32_t>(vi));
      ++k;
    }
    if (k != 3)
      throw std::runtime_error(
          "the union of two meshes has a face that is not a triangle");
    f.push_back(face);
  }
  return TriangleMesh(std::move(v), std::move(f));
}

bool MeshesIntersect(const TriangleMesh& a, const TriangleMesh& b) {
  if (BoxesApart(a, b, 0)) return false;
  const Mesh ma = ToCgalMesh(a), mb = ToCgalMesh(b);
  // Surfaces crossing, or one solid wholly inside the other (closed meshes).
  return PMP::do_intersect(ma, mb,
                           CGAL::parameters::do_overlap_test_of_bounded_sides(true),
                           CGAL::parameters::do_overlap_test_of_bounded_sides(true));
}

MeshContact MeasureContact(const TriangleMesh& a, const TriangleMesh& b) {
  MeshContact c;
  c.intersect = MeshesIntersect(a, b);
  if (c.intersect) return c;
  const Mesh ma = ToCgalMesh(a), mb = ToCgalMesh(b);
  Tree ta(faces(ma).first, faces(ma).second, ma),
      tb(faces(mb).first, faces(mb).second, mb);
  ta.accelerate_distance_queries();
  tb.accelerate_distance_queries();
  c.gap_mm = std::min(VertexGap(b, ta), VertexGap(a, tb));
  return c;
}

std::vector<bool> InsideSolid(const TriangleMesh& solid,
                              const std::vector<Vector3>& points) {
  const Mesh m = ToCgalMesh(solid);
  Tree tree(faces(m).first, faces(m).second, m);
  const CGAL::Side_of_triangle_mesh<Mesh, K> side(tree);
  std::vector<bool> out;
  out.reserve(points.size());
  for (const Vector3& p : points)
    out.push_back(side(Point(p.x(), p.y(), p.z())) != CGAL::ON_UNBOUNDED_SIDE);
  return out;
}

}  // namespace sulcus
