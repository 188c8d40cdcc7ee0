#include "core/spheretree/mesh_oracle.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <vector>

namespace sulcus {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
using Traits = CGAL::AABB_traits<K, Primitive>;
using Tree = CGAL::AABB_tree<Traits>;
using Side = CGAL::Side_of_triangle_mesh<Mesh, K>;
}  // namespace

struct MeshOracle::Impl {
  Mesh mesh;
  Tree tree;
  std::unique_ptr<Side> side;
};

MeshOracle::MeshOracle(const TriangleMesh& input) : impl_(std::make_unique<Impl>()) {
  Mesh& m = impl_->mesh;
  std::vector<Mesh::Vertex_index> vi;
  vi.reserve(input.num_vertices());
  for (const Vector3& v : input.vertices())
    vi.push_back(m.add_vertex(Point(v.x(), v.y(), v.z())));
  for (const auto& f : input.faces()) {
    // Faces Surface_mesh refuses (non-manifold) cannot be here: callers validate.
    m.add_face(vi[f[0]], vi[f[1]], vi[f[2]]);
  }
  impl_->tree.insert(faces(m).first, faces(m).second, m);
  impl_->tree.accelerate_distance_queries();
  impl_->side = std::make_unique<Side>(impl_->tree);
}

MeshOracle::~MeshOracle() = default;

bool MeshOracle::Inside(const Vector3& p) const {
  return (*impl_->side)(Point(p.x(), p.y(), p.z())) != CGAL::ON_UNBOUNDED_SIDE;
}

double MeshOracle::Distance(const Vector3& p) const {
  return std::sqrt(impl_->tree.squared_distance(Point(p.x(), p.y(), p.z())));
}

}  // namespace sulcus
