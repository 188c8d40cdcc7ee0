#include "core/spheretree/octree_builder.h"

#include <cmath>
#include <map>

namespace sulcus {
namespace {

// Conservative triangle-versus-box test: the triangle's bounding box overlaps the
// box and its plane crosses it. A superset of the exact test, so no covered cell
// is missed.
bool MayIntersect(const Vector3& a, const Vector3& b, const Vector3& c, const Vector3& lo,
                  const Vector3& hi) {
  const Vector3 tmin = a.cwiseMin(b).cwiseMin(c), tmax = a.cwiseMax(b).cwiseMax(c);
  if ((tmin.array() > hi.array()).any() || (tmax.array() < lo.array()).any())
    return false;
  const Vector3 n = (b - a).cross(c - a);
  const Vector3 center = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  const double r = half.dot(n.cwiseAbs());
  return std::abs(n.dot(center - a)) <= r;
}

}  // namespace

SphereTree BuildOctreeSphereTree(const TriangleMesh& mesh, int levels) {
  const Aabb box = mesh.Bounds();
  const double size = box.LargestExtent() * (1 + 1e-9);
  const Vector3 origin = 0.5 * (box.min + box.max) - Vector3::Constant(size / 2);
  SphereTree tree;
  tree.levels = levels;
  tree.branching = 8;
  // Breadth-first: each node keeps its cell (integer coordinates at its level)
  // and the faces that may cross it.
  struct Cell {
    int i, j, k;
    std::vector<std::int32_t> faces;
  };
  std::vector<Cell> cells;
  std::vector<std::int32_t> all(mesh.num_faces());
  for (std::size_t f = 0; f < all.size(); ++f) all[f] = static_cast<std::int32_t>(f);
  const double slack = 1e-12 * size;
  tree.AddNode(origin + Vector3::Constant(size / 2),
               size * std::sqrt(3.0) / 2 + slack * levels, 0);
  cells.push_back({0, 0, 0, all});
  for (std::size_t n = 0; n < tree.size(); ++n) {
    const int lvl = tree.level[n];
    if (lvl + 1 >= levels) continue;
    const double child = size / std::pow(2.0, lvl + 1);
    tree.first_child[n] = static_cast<std::int32_t>(tree.size());
    for (int o = 0; o < 8; ++o) {
      Cell c{2 * cells[n].i + (o & 1),
             2 * cells[n].j + ((o >> 1) & 1),
             2 * cells[n].k + ((o >> 2) & 1),
             {}};
      const Vector3 lo = origin + child * Vector3(c.i, c.j, c.k),
                    hi = lo + Vector3::Constant(child);
      for (std::int32_t f : cells[n].faces) {
        const auto& t = mesh.faces()[f];
        if (MayIntersect(mesh.vertices()[t[0]], mesh.vertices()[t[1]],
                         mesh.vertices()[t[2]], lo, hi)) {
          c.faces.push_back(f);
        }
      }
      if (c.faces.empty()) continue;
      // A slightly larger radius at each level keeps children strictly inside.
      tree.AddNode(0.5 * (lo + hi),
                   child * std::sqrt(3.0) / 2 + slack * (levels - lvl - 1), lvl + 1);
      cells.push_back(std::move(c));
      ++tree.child_count[n];
    }
    if (tree.child_count[n] == 0) tree.first_child[n] = 0;
    cells[n].faces.clear();
    cells[n].faces.shrink_to_fit();
  }
  return tree;
}

}  // namespace sulcus
