#include "core/geometry/simplify.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModAspectRatioT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <queue>
#include <vector>

namespace sulcus {
namespace {

// The rules both decimations follow (simplify.h).
constexpr double kMaxNormalTurnDeg = 30.0;
constexpr double kMaxAspect = 8.0;

// A weighted sum of squared distances to planes, as the symmetric 4x4 matrix of the
// plane quadrics (Garland and Heckbert): 10 coefficients.
struct Quadric {
  double a2 = 0, ab = 0, ac = 0, ad = 0, b2 = 0, bc = 0, bd = 0, c2 = 0, cd = 0, d2 = 0;

  // The plane n . x + d = 0 (n a unit vector), weighted by w.
  void AddPlane(const Vector3& n, double d, double w) {
    a2 += w * n.x() * n.x();
    ab += w * n.x() * n.y();
    ac += w * n.x() * n.z();
    ad += w * n.x() * d;
    b2 += w * n.y() * n.y();
    bc += w * n.y() * n.z();
    bd += w * n.y() * d;
    c2 += w * n.z() * n.z();
    cd += w * n.z() * d;
    d2 += w * d * d;
  }
  void Add(const Quadric& o) {
    a2 += o.a2;
    ab += o.ab;
    ac += o.ac;
    ad += o.ad;
    b2 += o.b2;
    bc += o.bc;
    bd += o.bd;
    c2 += o.c2;
    cd += o.cd;
    d2 += o.d2;
  }
  // The weighted sum of squared distances of p to the planes.
  double At(const Vector3& p) const {
    const double x = p.x(), y = p.y(), z = p.z();
    return x * (a2 * x + 2 * (ab * y + ac * z + ad)) + y * (b2 * y + 2 * (bc * z + bd)) +
           z * (c2 * z + 2 * cd) + d2;
  }
};

// The inverse of a triangle's aspect ratio (its longest edge over the height
// on it): 1 / (l^2 / |2 area|); 0 for a degenerate triangle.
double InverseAspect(const Vector3& a, const Vector3& b, const Vector3& c) {
  const double l2 =
      std::max({(a - b).squaredNorm(), (b - c).squaredNorm(), (c - a).squaredNorm()});
  const double twice_area = (b - a).cross(c - a).norm();
  return l2 > 0 ? twice_area / l2 : 0.0;
}

// Halfedge collapses (a vertex moved onto a neighbour and merged with it, so
// every vertex left is one of the input's), cheapest first by the quadric
// error: each vertex is on a heap at its cheapest collapse's error, refreshed
// round every collapse, and its collapses are checked when it comes up.
class Decimator {
 public:
  Decimator(const TriangleMesh& in, double max_error_mm)
      : p_(in.vertices()),
        f_(in.faces()),
        max_error2_(max_error_mm * max_error_mm),
        min_cos_(std::cos(kMaxNormalTurnDeg * std::numbers::pi / 180.0)),
        min_inverse_aspect_(1.0 / kMaxAspect) {
    const std::size_t nv = p_.size(), nf = f_.size();
    vf_.resize(nv);
    q_.resize(nv);
    locked_.assign(nv, 0);
    alive_.assign(nv, 1);
    face_alive_.assign(nf, 1);
    normal_.resize(nf);
    inverse_aspect_.resize(nf);
    stamp_.assign(nv, 0);
    mark_.assign(nv, 0);
    for (std::size_t f = 0; f < nf; ++f) {
      for (const std::int32_t v : f_[f]) vf_[v].push_back(static_cast<std::int32_t>(f));
      UpdateFace(static_cast<std::int32_t>(f));
      const Vector3& n = normal_[f];
      if (n.squaredNorm() == 0) continue;
      const Vector3 &a = p_[f_[f][0]], &b = p_[f_[f][1]], &c = p_[f_[f][2]];
      const double area = 0.5 * (b - a).cross(c - a).norm();
      const double d = -n.dot(a);
      for (const std::int32_t v : f_[f]) q_[v].AddPlane(n, d, area);
    }
    LockBorders();
  }

  TriangleMesh Run() {
    for (std::int32_t v = 0; v < static_cast<std::int32_t>(p_.size()); ++v) Refresh(v);
    while (!heap_.empty()) {
      const Entry e = heap_.top();
      heap_.pop();
      if (alive_[e.v] && e.stamp == stamp_[e.v]) Visit(e.v);
    }
    return Compact();
  }

 private:
  struct Entry {
    double cost;
    std::int32_t v;
    std::uint32_t stamp;
    // The heap's top is the cheapest; ties go to the lower vertex.
    bool operator<(const Entry& o) const {
      return cost != o.cost ? cost > o.cost : v > o.v;
    }
  };

  void UpdateFace(std::int32_t f) {
    const Vector3 &a = p_[f_[f][0]], &b = p_[f_[f][1]], &c = p_[f_[f][2]];
    const Vector3 n = (b - a).cross(c - a);
    const double len = n.norm();
    normal_[f] = len > 0 && std::isfinite(len) ? Vector3(n / len) : Vector3::Zero();
    inverse_aspect_[f] = InverseAspect(a, b, c);
  }

  // Vertices on an edge that is not shared by exactly two faces, or whose
  // faces do not make one fan, stay where they are: a border stays as it is
  // and nothing is joined that was apart.
  void LockBorders() {
    std::vector<std::uint64_t> edges;
    edges.reserve(3 * f_.size());
    for (const TriangleMesh::Face& f : f_) {
      for (int k = 0; k < 3; ++k) {
        const auto a = static_cast<std::uint32_t>(f[k]);
        const auto b = static_cast<std::uint32_t>(f[(k + 1) % 3]);
        edges.push_back((static_cast<std::uint64_t>(std::min(a, b)) << 32) |
                        std::max(a, b));
      }
    }
    std::sort(edges.begin(), edges.end());
    for (std::size_t i = 0; i < edges.size();) {
      std::size_t j = i;
      while (j < edges.size() && edges[j] == edges[i]) ++j;
      if (j - i != 2) {
        locked_[edges[i] >> 32] = 1;
        locked_[edges[i] & 0xffffffffu] = 1;
      }
      i = j;
    }
    for (std::size_t v = 0; v < p_.size(); ++v) {
      // A closed fan has as many neighbours as faces.
      if (!locked_[v] && Ring(static_cast<std::int32_t>(v)).size() != vf_[v].size())
        locked_[v] = 1;
    }
  }

  // The vertices that share a face with v, each once, into `out`.
  void RingInto(std::int32_t v, std::vector<std::int32_t>* out) {
    out->clear();
    const std::uint32_t tick = NextMark();
    for (const std::int32_t f : vf_[v]) {
      for (const std::int32_t w : f_[f]) {
        if (w != v && mark_[w] != tick) {
          mark_[w] = tick;
          out->push_back(w);
        }
      }
    }
  }
  const std::vector<std::int32_t>& Ring(std::int32_t v) {
    RingInto(v, &ring_);
    return ring_;
  }

  std::uint32_t NextMark() {
    if (++tick_ == 0) {  // wrapped: clear the marks once
      std::fill(mark_.begin(), mark_.end(), 0);
      tick_ = 1;
    }
    return tick_;
  }

  static bool Has(const TriangleMesh::Face& f, std::int32_t v) {
    return f[0] == v || f[1] == v || f[2] == v;
  }

  // The quadric error of moving u onto v (u's planes and v's, at v).
  double Error(std::int32_t u, std::int32_t v) const {
    Quadric q = q_[u];
    q.Add(q_[v]);
    return std::max(0.0, q.At(p_[v]));
  }

  // Whether u may move onto v: not when that would change the surface's
  // topology, turn a face by more than the limit or leave a sliver where there
  // was none.
  bool Legal(std::int32_t u, std::int32_t v) {
    if (locked_[u]) return false;
    // The two faces on the edge, and the vertices opposite it.
    std::int32_t opposite[2] = {-1, -1};
    int shared = 0;
    for (const std::int32_t f : vf_[u]) {
      if (!Has(f_[f], v)) continue;
      if (shared == 2) return false;
      for (const std::int32_t w : f_[f])
        if (w != u && w != v) opposite[shared] = w;
      ++shared;
    }
    if (shared != 2 || opposite[0] == opposite[1]) return false;
    // Three faces at least stay round each opposite vertex.
    for (const std::int32_t w : opposite)
      if (vf_[w].size() <= 3) return false;
    // The link condition: u and v have no neighbour in common but the two
    // opposite vertices.
    const std::uint32_t of_u = NextMark();
    for (const std::int32_t f : vf_[u])
      for (const std::int32_t w : f_[f]) mark_[w] = of_u;
    mark_[opposite[0]] = mark_[opposite[1]] = 0;
    for (const std::int32_t f : vf_[v])
      for (const std::int32_t w : f_[f])
        if (w != u && w != v && mark_[w] == of_u) return false;
    // The faces that stay, u moved onto v: no turn past the limit, no sliver.
    double before = 1, after = 1;
    for (const std::int32_t f : vf_[u]) {
      before = std::min(before, inverse_aspect_[f]);
      if (Has(f_[f], v)) continue;
      Vector3 c[3];
      for (int k = 0; k < 3; ++k) c[k] = f_[f][k] == u ? p_[v] : p_[f_[f][k]];
      const Vector3 n = (c[1] - c[0]).cross(c[2] - c[0]);
      const double len = n.norm();
      if (!(len > 0)) return false;
      if (normal_[f].squaredNorm() > 0 && normal_[f].dot(n) < min_cos_ * len)
        return false;
      after = std::min(after, InverseAspect(c[0], c[1], c[2]));
    }
    return after > before || after > min_inverse_aspect_;
  }

  // v's neighbours within the error bound, cheapest first, into by_error_.
  void Candidates(std::int32_t v) {
    RingInto(v, &candidates_);
    by_error_.clear();
    for (const std::int32_t w : candidates_) {
      const double e = Error(v, w);
      if (e <= max_error2_) by_error_.push_back({e, w});
    }
    std::sort(by_error_.begin(), by_error_.end());
  }

  // v on the heap at its cheapest collapse's error, legal or not: legality is
  // checked when it comes up (most vertices are refreshed several times
  // before).
  void Refresh(std::int32_t v) {
    ++stamp_[v];
    if (!alive_[v] || locked_[v]) return;
    Candidates(v);
    if (!by_error_.empty()) heap_.push({by_error_.front().first, v, stamp_[v]});
  }

  // v has come up: its cheapest legal collapse is made, or v goes back on the
  // heap at that collapse's error when another vertex is cheaper now; with
  // none legal, v waits until its neighbourhood changes.
  void Visit(std::int32_t v) {
    Candidates(v);
    for (const auto& [e, w] : by_error_) {
      if (!heap_.empty() && e > heap_.top().cost) {
        heap_.push({e, v, stamp_[v]});
        return;
      }
      if (Legal(v, w)) {
        Collapse(v, w);
        return;
      }
    }
  }

  void Collapse(std::int32_t u, std::int32_t v) {
    for (const std::int32_t f : vf_[u]) {
      if (Has(f_[f], v)) {
        face_alive_[f] = 0;
        for (const std::int32_t w : f_[f]) {
          if (w == u) continue;
          auto& list = vf_[w];
          list.erase(std::find(list.begin(), list.end(), f));
        }
        continue;
      }
      for (std::int32_t& w : f_[f])
        if (w == u) w = v;
      vf_[v].push_back(f);
      UpdateFace(f);
    }
    vf_[u].clear();
    alive_[u] = 0;
    q_[v].Add(q_[u]);
    RingInto(v, &neighbours_);
    Refresh(v);
    for (const std::int32_t w : neighbours_) Refresh(w);
  }

  TriangleMesh Compact() const {
    std::vector<std::int32_t> index(p_.size(), -1);
    std::vector<Vector3> vertices;
    std::vector<TriangleMesh::Face> faces;
    for (std::size_t f = 0; f < f_.size(); ++f) {
      if (!face_alive_[f]) continue;
      for (const std::int32_t v : f_[f]) index[v] = 0;
    }
    for (std::size_t v = 0; v < p_.size(); ++v) {
      if (index[v] < 0) continue;
      index[v] = static_cast<std::int32_t>(vertices.size());
      vertices.push_back(p_[v]);
    }
    for (std::size_t f = 0; f < f_.size(); ++f) {
      if (!face_alive_[f]) continue;
      faces.push_back({index[f_[f][0]], index[f_[f][1]], index[f_[f][2]]});
    }
    return TriangleMesh(std::move(vertices), std::move(faces));
  }

  std::vector<Vector3> p_;
  std::vector<TriangleMesh::Face> f_;
  double max_error2_, min_cos_, min_inverse_aspect_;
  std::vector<std::vector<std::int32_t>> vf_;  // the faces round each vertex
  std::vector<Quadric> q_;
  std::vector<char> locked_, alive_, face_alive_;
  std::vector<Vector3> normal_;  // unit, zero for a degenerate face
  std::vector<double> inverse_aspect_;
  std::vector<std::uint32_t> stamp_;
  std::priority_queue<Entry> heap_;
  std::vector<std::uint32_t> mark_;
  std::uint32_t tick_ = 0;
  std::vector<std::int32_t> ring_, candidates_, neighbours_;
  std::vector<std::pair<double, std::int32_t>> by_error_;
};

struct Traits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};
using Mesh = OpenMesh::TriMesh_ArrayKernelT<Traits>;

// OpenMesh's mesh with its own topology check for a collapse (the decimater
// calls the mesh type's is_collapse_ok, which this hides): the same test as
// OpenMesh's TriConnectivity, with the one-rings' intersection marked in a
// vector of stamps, where the library's allocates and looks properties up by
// name at every call (about 40 % of the decimation's time).
class MeshWithFastCheck : public Mesh {
 public:
  bool is_collapse_ok(HalfedgeHandle v0v1) {
    if (status(edge_handle(v0v1)).deleted()) return false;
    const HalfedgeHandle v1v0 = opposite_halfedge_handle(v0v1);
    const VertexHandle v0 = to_vertex_handle(v1v0), v1 = to_vertex_handle(v0v1);
    if (status(v0).deleted() || status(v1).deleted()) return false;
    // The two edges from the edge's ends to each opposite vertex may not both
    // be on a border.
    VertexHandle vl, vr;
    auto side = [&](HalfedgeHandle h, VertexHandle* opposite) {
      if (is_boundary(h)) return true;
      const HalfedgeHandle h1 = next_halfedge_handle(h), h2 = next_halfedge_handle(h1);
      *opposite = to_vertex_handle(h1);
      return !(is_boundary(opposite_halfedge_handle(h1)) &&
               is_boundary(opposite_halfedge_handle(h2)));
    };
    if (!side(v0v1, &vl) || !side(v1v0, &vr)) return false;
    if (vl == vr) return false;  // equal, or both invalid
    // The one-rings of v0 and v1 meet only at vl and vr.
    if (stamp_.size() < n_vertices()) stamp_.resize(n_vertices(), 0);
    if (++tick_ == 0) {
      std::fill(stamp_.begin(), stamp_.end(), 0);
      tick_ = 1;
    }
    for (const VertexHandle v : vv_range(v1)) stamp_[v.idx()] = tick_;
    for (const VertexHandle v : vv_range(v0))
      if (stamp_[v.idx()] == tick_ && v != vl && v != vr) return false;
    // An edge between two border vertices must be a border edge.
    return !(is_boundary(v0) && is_boundary(v1) && !is_boundary(v0v1) &&
             !is_boundary(v1v0));
  }

 private:
  std::vector<std::uint32_t> stamp_;
  std::uint32_t tick_ = 0;
};

template <typename M>
TriangleMesh DecimateWithOpenMesh(const TriangleMesh& in, double max_error_mm) {
  M m;
  std::vector<typename M::VertexHandle> handles;
  handles.reserve(in.num_vertices());
  for (const Vector3& v : in.vertices())
    handles.push_back(m.add_vertex(typename M::Point(v.x(), v.y(), v.z())));
  for (const auto& f : in.faces())
    m.add_face(handles[f[0]], handles[f[1]], handles[f[2]]);
  m.request_face_normals();
  m.update_face_normals();
  OpenMesh::Decimater::DecimaterT<M> decimater(m);
  typename OpenMesh::Decimater::ModQuadricT<M>::Handle quadric;
  typename OpenMesh::Decimater::ModNormalFlippingT<M>::Handle flipping;
  typename OpenMesh::Decimater::ModAspectRatioT<M>::Handle aspect;
  decimater.add(quadric);
  decimater.add(flipping);
  decimater.add(aspect);
  decimater.module(quadric).set_max_err(max_error_mm * max_error_mm);
  decimater.module(flipping).set_max_normal_deviation(kMaxNormalTurnDeg);
  decimater.module(aspect).set_aspect_ratio(kMaxAspect);
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

}  // namespace

TriangleMesh Simplify(const TriangleMesh& mesh, double max_error_mm) {
  return Decimator(mesh, max_error_mm).Run();
}

TriangleMesh SimplifyWithOpenMesh(const TriangleMesh& mesh, double max_error_mm,
                                  bool library_collapse_check) {
  return library_collapse_check
             ? DecimateWithOpenMesh<Mesh>(mesh, max_error_mm)
             : DecimateWithOpenMesh<MeshWithFastCheck>(mesh, max_error_mm);
}

}  // namespace sulcus
