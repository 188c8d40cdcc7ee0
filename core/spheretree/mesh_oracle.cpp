#include "core/spheretree/mesh_oracle.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Side_of_triangle_mesh.h>

#include <cmath>
#include <vector>

#include "core/geometry/cgal_internal.h"

namespace sulcus {
namespace {
using K = CgalKernel;
using Point = CgalPoint;
using Mesh = CgalMesh;
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
  impl_->mesh = ToCgalMesh(input);  // callers validate: no face is refused
  const Mesh& m = impl_->mesh;
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
