#include "core/geometry/mesh.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

namespace sulcus {
namespace {

// Relative to the squared bounding-box diagonal: a face smaller than this has no
// usable normal (1e-14 keeps sliver faces of a 1 m part at 1e-8 mm^2 legal).
constexpr double kDegenerateAreaRel = 1e-14;

std::size_t FindRoot(std::vector<std::size_t>& parent, std::size_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

// Counts vertices whose incident faces do not form a single fan (a "pinch"). The link of
// a vertex (the edges opposite it in its faces) is one path or cycle on a manifold; each
// extra connected component of the link is another sheet touching there.
std::size_t CountNonManifoldVertices(const std::vector<TriangleMesh::Face>& faces) {
  struct LinkEdge {
    std::int32_t vertex, a, b;
  };
  std::vector<LinkEdge> link;
  link.reserve(faces.size() * 3);
  for (const auto& f : faces) {
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) continue;
    for (int k = 0; k < 3; ++k) link.push_back({f[k], f[(k + 1) % 3], f[(k + 2) % 3]});
  }
  std::sort(link.begin(), link.end(),
            [](const LinkEdge& x, const LinkEdge& y) { return x.vertex < y.vertex; });
  std::size_t count = 0;
  std::vector<std::int32_t> ids;
  std::vector<std::size_t> parent;
  for (std::size_t i = 0; i < link.size();) {
    std::size_t j = i;
    while (j < link.size() && link[j].vertex == link[i].vertex) ++j;
    ids.clear();
    for (std::size_t k = i; k < j; ++k) {
      ids.push_back(link[k].a);
      ids.push_back(link[k].b);
    }
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    parent.resize(ids.size());
    std::iota(parent.begin(), parent.end(), 0);
    auto local = [&](std::int32_t v) {
      return static_cast<std::size_t>(std::lower_bound(ids.begin(), ids.end(), v) -
                                      ids.begin());
    };
    std::size_t components = ids.size();
    for (std::size_t k = i; k < j; ++k) {
      const std::size_t a = FindRoot(parent, local(link[k].a));
      const std::size_t b = FindRoot(parent, local(link[k].b));
      if (a != b) {
        parent[a] = b;
        --components;
      }
    }
    count += components > 1;
    i = j;
  }
  return count;
}

}  // namespace

TriangleMesh::TriangleMesh(std::vector<Vector3> vertices, std::vector<Face> faces)
    : vertices_(std::move(vertices)), faces_(std::move(faces)) {}

Aabb TriangleMesh::Bounds() const {
  Aabb box;
  for (const Vector3& v : vertices_) box.Extend(v);
  return box;
}

double TriangleMesh::Volume() const {
  double six_v = 0;
  for (const Face& f : faces_) {
    six_v += vertices_[f[0]].dot(vertices_[f[1]].cross(vertices_[f[2]]));
  }
  return six_v / 6.0;
}

double TriangleMesh::SurfaceArea() const {
  double twice = 0;
  for (const Face& f : faces_) {
    twice += (vertices_[f[1]] - vertices_[f[0]])
                 .cross(vertices_[f[2]] - vertices_[f[0]])
                 .norm();
  }
  return twice / 2.0;
}

std::vector<Vector3> TriangleMesh::VertexNormalSums() const {
  std::vector<Vector3> n(vertices_.size(), Vector3::Zero());
  for (const Face& f : faces_) {
    const Vector3 a =
        (vertices_[f[1]] - vertices_[f[0]]).cross(vertices_[f[2]] - vertices_[f[0]]);
    for (int k = 0; k < 3; ++k) n[f[k]] += a;
  }
  return n;
}

Vector3 TriangleMesh::FaceNormal(std::size_t i) const {
  const Face& f = faces_[i];
  const Vector3 n =
      (vertices_[f[1]] - vertices_[f[0]]).cross(vertices_[f[2]] - vertices_[f[0]]);
  const double len = n.norm();
  return len > 0 ? Vector3(n / len) : Vector3::Zero();
}

MeshReport TriangleMesh::Check() const {
  MeshReport r;
  r.num_vertices = vertices_.size();
  r.num_faces = faces_.size();
  r.bounds = Bounds();
  r.volume = Volume();
  r.area = SurfaceArea();

  const double diag2 = r.bounds.empty() ? 0.0 : r.bounds.extent().squaredNorm();
  std::vector<char> used(vertices_.size(), 0);
  // Directed edges (a, b, face), sorted so that each undirected edge is one run.
  struct Directed {
    std::int32_t lo, hi;
    bool forward;  // a < b
    std::uint32_t face;
  };
  std::vector<Directed> edges;
  edges.reserve(faces_.size() * 3);
  for (std::size_t i = 0; i < faces_.size(); ++i) {
    const Face& f = faces_[i];
    for (int k = 0; k < 3; ++k) used[f[k]] = 1;
    const double twice_area = (vertices_[f[1]] - vertices_[f[0]])
                                  .cross(vertices_[f[2]] - vertices_[f[0]])
                                  .norm();
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2] ||
        !(twice_area > 2.0 * kDegenerateAreaRel * diag2)) {
      ++r.degenerate_faces;
    }
    for (int k = 0; k < 3; ++k) {
      const std::int32_t a = f[k], b = f[(k + 1) % 3];
      if (a == b) continue;
      edges.push_back(
          {std::min(a, b), std::max(a, b), a < b, static_cast<std::uint32_t>(i)});
    }
  }
  r.unreferenced_vertices =
      static_cast<std::size_t>(std::count(used.begin(), used.end(), 0));
  std::sort(edges.begin(), edges.end(), [](const Directed& x, const Directed& y) {
    return std::tie(x.lo, x.hi, x.forward) < std::tie(y.lo, y.hi, y.forward);
  });

  std::vector<std::size_t> parent(faces_.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    std::size_t fwd = 0;
    while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) {
      fwd += edges[j].forward;
      const std::size_t a = FindRoot(parent, edges[i].face),
                        b = FindRoot(parent, edges[j].face);
      if (a != b) parent[a] = b;
      ++j;
    }
    const std::size_t uses = j - i;
    ++r.num_edges;
    if (uses == 1) ++r.boundary_edges;
    if (uses > 2) ++r.nonmanifold_edges;
    if (uses == 2 && fwd != 1) ++r.misoriented_edges;
    i = j;
  }
  for (std::size_t i = 0; i < faces_.size(); ++i)
    r.components += FindRoot(parent, i) == i;
  r.euler_characteristic = static_cast<int>(r.num_vertices - r.unreferenced_vertices) -
                           static_cast<int>(r.num_edges) + static_cast<int>(r.num_faces);
  // A non-manifold edge already makes its vertices' links branch; count pinched
  // vertices only where every edge is manifold, so each fault is reported once.
  if (r.nonmanifold_edges == 0) {
    r.nonmanifold_vertices = CountNonManifoldVertices(faces_);
  }
  return r;
}

void TriangleMesh::Transform(const Matrix3& R, const Vector3& t) {
  for (Vector3& v : vertices_) v = R * v + t;
}

void TriangleMesh::FlipOrientation() {
  for (Face& f : faces_) std::swap(f[1], f[2]);
}

}  // namespace sulcus
