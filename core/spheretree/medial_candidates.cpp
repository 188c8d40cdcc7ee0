// Medial candidates: centres of spheres deep inside the solid, from the inner
// Voronoi poles of surface samples (the first stage of the sphere-tree builder).
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <utility>

#include "core/geometry/cgal_internal.h"
#include "core/spheretree/builder_stages.h"
#include "core/spheretree/mesh_oracle.h"

namespace sulcus::tree_build {
namespace {

using K = CgalKernel;

// Keeps the deepest candidate in each cell of a grid `cell` wide, in the input's
// order.
std::vector<Candidate> ThinCandidates(std::vector<Candidate> cands, double cell) {
  std::unordered_map<std::uint64_t, std::size_t> best;
  best.reserve(cands.size());
  auto key = [&](const Vector3& p) {
    std::uint64_t k = 0;
    for (int a = 0; a < 3; ++a) {
      const auto i = static_cast<std::int64_t>(std::floor(p[a] / cell));
      k = k * 2097152u + static_cast<std::uint64_t>(i & 0x1FFFFF);  // 21 bits per axis
    }
    return k;
  };
  for (std::size_t i = 0; i < cands.size(); ++i) {
    auto [it, fresh] = best.emplace(key(cands[i].c), i);
    if (!fresh && cands[i].depth > cands[it->second].depth) it->second = i;
  }
  std::vector<char> keep(cands.size(), 0);
  for (const auto& entry : best) keep[entry.second] = 1;
  std::vector<Candidate> out;
  out.reserve(best.size());
  for (std::size_t i = 0; i < cands.size(); ++i) {
    if (keep[i]) out.push_back(cands[i]);
  }
  return out;
}

// Centre of the sphere through four points; false for a (nearly) flat tetrahedron,
// whose circumcentre is at or near infinity.
bool Circumcenter(const Vector3 (&p)[4], Vector3* center) {
  const Vector3 a = p[1] - p[0], b = p[2] - p[0], c = p[3] - p[0];
  const double den = 2.0 * a.dot(b.cross(c));
  if (!(std::abs(den) > 1e-12 * a.norm() * b.norm() * c.norm())) return false;
  *center = p[0] + (a.squaredNorm() * b.cross(c) + b.squaredNorm() * c.cross(a) +
                    c.squaredNorm() * a.cross(b)) /
                       den;
  return center->allFinite();
}

// Candidate centres: the inner Voronoi pole of each surface sample (the farthest
// Voronoi vertex of its cell on the inner side, Amenta's pole), plus points on
// the way from each sample to its pole, so that thin and sharp regions have

}  // namespace

std::vector<Candidate> MedialCandidates(const std::vector<Vector3>& samples,
                                        const std::vector<Vector3>& normals, double diag,
                                        double thin_cell, const MeshOracle& oracle,
                                        const Reporter& report) {
  using Vb = CGAL::Triangulation_vertex_base_with_info_3<std::int32_t, K>;
  using Tds = CGAL::Triangulation_data_structure_3<Vb>;
  using Delaunay = CGAL::Delaunay_triangulation_3<K, Tds>;
  std::vector<std::pair<K::Point_3, std::int32_t>> points;
  points.reserve(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    points.emplace_back(K::Point_3(samples[i].x(), samples[i].y(), samples[i].z()),
                        static_cast<std::int32_t>(i));
  }
  const Delaunay dt(points.begin(), points.end());
  report("medial axis: Delaunay done", 0.25);

  std::vector<double> best(samples.size(), 0.0);
  std::vector<Vector3> pole(samples.size(), Vector3::Zero());
  const double max2 = diag * diag;
  for (auto cell : dt.finite_cell_handles()) {
    Vector3 corner[4];
    for (int k = 0; k < 4; ++k) {
      const K::Point_3& q = cell->vertex(k)->point();
      corner[k] = Vector3(q.x(), q.y(), q.z());
    }
    Vector3 center;
    if (!Circumcenter(corner, &center)) continue;  // a flat sliver: no Voronoi vertex
    for (int k = 0; k < 4; ++k) {
      const std::int32_t s = cell->vertex(k)->info();
      const Vector3 d = center - samples[s];
      const double d2 = d.squaredNorm();
      if (d.dot(normals[s]) < 0 && d2 > best[s] && d2 < max2) {
        best[s] = d2;
        pole[s] = center;
      }
    }
  }

  // Each with its distance to the sample it came from, an upper bound of its
  // depth, until the mesh is asked.
  std::vector<Candidate> points_to_try;
  points_to_try.reserve(samples.size() * 3);
  for (std::size_t s = 0; s < samples.size(); ++s) {
    if (best[s] > 0) {
      const double reach = std::sqrt(best[s]);
      points_to_try.push_back({pole[s], reach});
      for (double f : {0.15, 0.45})
        points_to_try.push_back({samples[s] + f * (pole[s] - samples[s]), f * reach});
    }
  }
  // The deepest-looking point in each cell of the grid: neighbours that close
  // enclose nearly the same pieces, and fewer candidates make the cover lists
  // shorter and the mesh queries fewer.
  points_to_try = ThinCandidates(std::move(points_to_try), thin_cell);

  std::vector<Candidate> out;
  out.reserve(points_to_try.size());
  const double min_depth = 1e-7 * diag;
  for (std::size_t i = 0; i < points_to_try.size(); ++i) {
    if (i % 2048 == 0)
      report("medial axis: depths", 0.25 + 0.75 * i / points_to_try.size());
    const Vector3& p = points_to_try[i].c;
    if (!oracle.Inside(p)) continue;
    const double depth = oracle.Distance(p);
    if (depth > min_depth) out.push_back({p, depth});
  }
  return out;
}

}  // namespace sulcus::tree_build
