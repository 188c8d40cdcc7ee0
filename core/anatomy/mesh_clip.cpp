#include "core/anatomy/mesh_clip.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Triangulation_data_structure_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <cmath>
#include <cstdint>
#include <list>
#include <stdexcept>
#include <unordered_map>
#include <utility>

#include "core/geometry/cgal_internal.h"

namespace sulcus {
namespace {

// The cap: a constrained Delaunay triangulation of the cut's loops, its
// faces inside the solid found by nesting depth (odd: inside), as the
// triangulation of a polygon with holes is.
using K = CgalKernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<std::int32_t, K>;
using Fbi = CGAL::Triangulation_face_base_with_info_2<int, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbi>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt =
    CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;

// Faces reachable from `start` without crossing a constraint get `depth`;
// those across one are queued with depth + 1.
void MarkNesting(Cdt& cdt) {
  for (Cdt::Face_handle f : cdt.all_face_handles()) f->info() = -1;
  std::list<std::pair<Cdt::Face_handle, int>> border{{cdt.infinite_face(), 0}};
  while (!border.empty()) {
    const auto [start, depth] = border.front();
    border.pop_front();
    if (start->info() != -1) continue;
    std::list<Cdt::Face_handle> queue{start};
    while (!queue.empty()) {
      const Cdt::Face_handle f = queue.front();
      queue.pop_front();
      if (f->info() != -1) continue;
      f->info() = depth;
      for (int i = 0; i < 3; ++i) {
        const Cdt::Face_handle n = f->neighbor(i);
        if (n->info() != -1) continue;
        if (cdt.is_constrained(Cdt::Edge(f, i)))
          border.emplace_back(n, depth + 1);
        else
          queue.push_back(n);
      }
    }
  }
}

// One plane: the triangles on the keep side, those crossing it cut, and the
// cut closed by a cap.
TriangleMesh ClipByPlane(const TriangleMesh& solid, const ClipPlane& plane) {
  const std::vector<Vector3>& in = solid.vertices();
  // Signed distances past the plane; a vertex on it (or within a
  // millionth of a millimetre) counts as kept, just inside, so that the
  // plane meets the surface only inside edges and the cut's loops are simple.
  constexpr double kOnPlane = 1e-6;
  std::vector<double> d(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) {
    d[i] = (in[i] - plane.q).dot(plane.normal);
    if (std::abs(d[i]) < kOnPlane) d[i] = -kOnPlane;
  }
  std::vector<Vector3> vertices;
  std::vector<std::int32_t> kept(in.size(), -1);
  auto keep = [&](std::int32_t v) {
    if (kept[v] < 0) {
      kept[v] = static_cast<std::int32_t>(vertices.size());
      vertices.push_back(in[v]);
    }
    return kept[v];
  };
  std::unordered_map<std::uint64_t, std::int32_t> on_edge;
  auto crossing = [&](std::int32_t a, std::int32_t b) {
    if (a > b) std::swap(a, b);
    const std::uint64_t key =
        static_cast<std::uint64_t>(a) << 32 | static_cast<std::uint32_t>(b);
    auto [it, added] =
        on_edge.try_emplace(key, static_cast<std::int32_t>(vertices.size()));
    if (added) {
      const double t = d[a] / (d[a] - d[b]);
      Vector3 p = in[a] + t * (in[b] - in[a]);
      p -= (p - plane.q).dot(plane.normal) * plane.normal;  // (on it exactly)
      vertices.push_back(p);
    }
    return it->second;
  };
  std::vector<TriangleMesh::Face> faces;
  // Directed rim edges, as the kept faces run them: the cap runs each the
  // other way.
  std::vector<std::pair<std::int32_t, std::int32_t>> rim;
  for (const TriangleMesh::Face& f : solid.faces()) {
    int inside = 0;
    for (int k = 0; k < 3; ++k) inside += d[f[k]] < 0;
    if (inside == 0) continue;
    if (inside == 3) {
      faces.push_back({keep(f[0]), keep(f[1]), keep(f[2])});
      continue;
    }
    // The kept polygon, in the face's order (Sutherland-Hodgman on one plane).
    std::int32_t poly[4];
    int n = 0, enter = -1, leave = -1;
    for (int k = 0; k < 3; ++k) {
      const std::int32_t a = f[k], b = f[(k + 1) % 3];
      if (d[a] < 0) poly[n++] = keep(a);
      if ((d[a] < 0) != (d[b] < 0)) {
        if (d[a] < 0)
          leave = n;
        else
          enter = n;
        poly[n++] = crossing(a, b);
      }
    }
    for (int k = 1; k + 1 < n; ++k) faces.push_back({poly[0], poly[k], poly[k + 1]});
    rim.emplace_back(poly[leave], poly[enter]);  // (the kept part's edge along the plane)
  }
  if (faces.empty() || rim.empty())
    return TriangleMesh(std::move(vertices), std::move(faces));

  // The cap in plane coordinates.
  const Vector3 u = plane.normal.unitOrthogonal(), w = plane.normal.cross(u);
  Cdt cdt;
  std::unordered_map<std::int32_t, Cdt::Vertex_handle> handle;
  auto at = [&](std::int32_t v) {
    if (handle.count(v)) return;
    const Vector3 p = vertices[v] - plane.q;
    const std::size_t before = cdt.number_of_vertices();
    const Cdt::Vertex_handle h = cdt.insert(K::Point_2(p.dot(u), p.dot(w)));
    if (cdt.number_of_vertices() == before)
      throw std::invalid_argument(
          "clip: two points of the cut coincide (the mesh touches itself there)");
    h->info() = v;
    handle.emplace(v, h);
  };
  for (const auto& [a, b] : rim) at(a), at(b);
  try {
    for (const auto& [a, b] : rim) cdt.insert_constraint(handle.at(a), handle.at(b));
  } catch (const std::exception&) {
    throw std::invalid_argument(
        "clip: the cut's outline crosses itself (the mesh intersects itself)");
  }
  if (cdt.number_of_vertices() != handle.size())
    throw std::invalid_argument(
        "clip: the cut's outline crosses itself (the mesh intersects itself)");
  MarkNesting(cdt);
  // (u, w, normal) is right-handed, so a face counter-clockwise in (u, w),
  // as the triangulation's are, faces +normal: out of the kept solid.
  for (Cdt::Finite_faces_iterator f = cdt.finite_faces_begin();
       f != cdt.finite_faces_end(); ++f) {
    if (f->info() % 2 != 1) continue;
    faces.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  }
  return TriangleMesh(std::move(vertices), std::move(faces));
}

}  // namespace

TriangleMesh ClipByPlanes(const TriangleMesh& solid,
                          const std::vector<ClipPlane>& planes) {
  if (planes.empty()) return solid;
  const MeshReport r = solid.Check();
  if (!r.closed() || !r.manifold())
    throw std::invalid_argument("clip: the mesh is not a closed manifold surface");
  TriangleMesh out = solid;
  for (const ClipPlane& p : planes) out = ClipByPlane(out, p);
  return out;
}

}  // namespace sulcus
