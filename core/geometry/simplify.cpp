#include "core/geometry/simplify.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModAspectRatioT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

namespace sulcus {
namespace {

struct Traits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};
using Mesh = OpenMesh::TriMesh_ArrayKernelT<Traits>;

}  // namespace

TriangleMesh Simplify(const TriangleMesh& in, double max_error_mm) {
  Mesh m;
  std::vector<Mesh::VertexHandle> handles;
  handles.reserve(in.num_vertices());
  for (const Vector3& v : in.vertices())
    handles.push_back(m.add_vertex(Mesh::Point(v.x(), v.y(), v.z())));
  for (const auto& f : in.faces())
    m.add_face(handles[f[0]], handles[f[1]], handles[f[2]]);
  m.request_face_normals();
  m.update_face_normals();
  OpenMesh::Decimater::DecimaterT<Mesh> decimater(m);
  OpenMesh::Decimater::ModQuadricT<Mesh>::Handle quadric;
  OpenMesh::Decimater::ModNormalFlippingT<Mesh>::Handle flipping;
  OpenMesh::Decimater::ModAspectRatioT<Mesh>::Handle aspect;
  decimater.add(quadric);
  decimater.add(flipping);
  decimater.add(aspect);
  decimater.module(quadric).set_max_err(max_error_mm * max_error_mm);
  decimater.module(flipping).set_max_normal_deviation(30.0);
  decimater.module(aspect).set_aspect_ratio(8.0);
  decimater.initialize();
  decimater.decimate();
  m.garbage_collection();
  std::vector<Vector3> vertices;
  vertices.reserve(m.n_vertices());
  for (const auto vh : m.vertices()) {
    const auto& p = m.point(vh);
    vertices.emplace_back(p[0], p[1], p[2]);
  }
  std::vector<TriangleMesh::Face> faces;
  faces.reserve(m.n_faces());
  for (const auto fh : m.faces()) {
    TriangleMesh::Face f{};
    int k = 0;
    for (const auto vh : m.fv_range(fh)) f[k++] = vh.idx();
    faces.push_back(f);
  }
  return TriangleMesh(std::move(vertices), std::move(faces));
}

}  // namespace sulcus
