// The hierarchy: leaves grouped top-down into a B-ary tree whose parents are the
// smallest spheres enclosing their children (the builder's last stage).
#include <CGAL/Min_sphere_of_spheres_d.h>
#include <CGAL/Min_sphere_of_spheres_d_traits_3.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/geometry/cgal_internal.h"
#include "core/spheretree/builder.h"

namespace sulcus {
namespace {

using K = CgalKernel;

// Splits items (indices into centres) into at most `parts` groups by recursive
// bisection along the longest axis of their bounding box, sizes proportional.
void SplitGroup(std::vector<std::int32_t> items, int parts,
                const std::vector<Vector3>& centers,
                std::vector<std::vector<std::int32_t>>* out) {
  if (items.empty()) return;
  if (parts <= 1 || items.size() == 1) {
    out->push_back(std::move(items));
    return;
  }
  Aabb box;
  for (std::int32_t i : items) box.Extend(centers[i]);
  int axis;
  box.extent().maxCoeff(&axis);
  std::sort(items.begin(), items.end(), [&](std::int32_t a, std::int32_t b) {
    return centers[a][axis] != centers[b][axis] ? centers[a][axis] < centers[b][axis]
                                                : a < b;
  });
  const int left_parts = parts / 2;
  const std::size_t cut = items.size() * left_parts / parts;
  SplitGroup({items.begin(), items.begin() + cut}, left_parts, centers, out);
  SplitGroup({items.begin() + cut, items.end()}, parts - left_parts, centers, out);
}

}  // namespace

SphereTree BuildTreeFromLeaves(const std::vector<Vector3>& centers,
                               const std::vector<double>& radii, int levels,
                               int branching) {
  if (centers.empty() || centers.size() != radii.size()) {
    throw SphereTreeError("a tree needs at least one leaf, with one radius per centre");
  }
  const std::size_t capacity = LeafCapacity(levels, branching);
  if (centers.size() > capacity) {
    throw SphereTreeError(std::to_string(centers.size()) + " leaves do not fit in " +
                          std::to_string(levels) + " levels of " +
                          std::to_string(branching));
  }
  Aabb bounds;
  for (const Vector3& c : centers) bounds.Extend(c);
  const double extent =
      std::max(bounds.LargestExtent(), *std::max_element(radii.begin(), radii.end()));
  SphereTree tree;
  tree.levels = levels;
  tree.branching = branching;
  std::vector<std::int32_t> all(centers.size());
  std::iota(all.begin(), all.end(), 0);
  // Each node records the leaves below it; children are appended level by level
  // so that every node's children are contiguous (breadth-first order).
  std::vector<std::vector<std::int32_t>> below;
  tree.AddNode(Vector3::Zero(), 1.0, 0);
  below.push_back(all);
  for (std::size_t node = 0; node < below.size(); ++node) {
    const int lvl = tree.level[node];
    if (below[node].size() == 1 || lvl == levels - 1) continue;  // a leaf
    // As many children as allowed: balanced groups of n / branching leaves each
    // fit a child subtree, since n <= branching * capacity.
    const int parts =
        static_cast<int>(std::min<std::size_t>(branching, below[node].size()));
    std::vector<std::vector<std::int32_t>> groups;
    SplitGroup(below[node], parts, centers, &groups);
    tree.first_child[node] = static_cast<std::int32_t>(tree.size());
    tree.child_count[node] = static_cast<std::uint8_t>(groups.size());
    for (auto& g : groups) {
      tree.AddNode(Vector3::Zero(), 1.0, lvl + 1);
      below.push_back(std::move(g));
    }
  }
  // Leaves take their spheres; parents bound their children, deepest first.
  using MTraits = CGAL::Min_sphere_of_spheres_d_traits_3<K, double, CGAL::Tag_true>;
  using MinSphere = CGAL::Min_sphere_of_spheres_d<MTraits>;
  const double slack = 1e-12 * extent;  // round-off in the containment test
  for (std::size_t n = tree.size(); n-- > 0;) {
    if (tree.IsLeaf(n)) {
      const std::int32_t leaf = below[n].front();
      tree.x[n] = centers[leaf].x();
      tree.y[n] = centers[leaf].y();
      tree.z[n] = centers[leaf].z();
      tree.r[n] = radii[leaf];
      continue;
    }
    std::vector<MTraits::Sphere> kids;
    const std::int32_t first = tree.first_child[n], count = tree.child_count[n];
    for (std::int32_t c = first; c < first + count; ++c) {
      kids.emplace_back(K::Point_3(tree.x[c], tree.y[c], tree.z[c]), tree.r[c]);
    }
    MinSphere ms(kids.begin(), kids.end());
    auto it = ms.center_cartesian_begin();
    const Vector3 center(*it, *(it + 1), *(it + 2));
    double radius = 0;
    for (std::int32_t c = first; c < first + count; ++c) {
      radius = std::max(radius, (tree.center(c) - center).norm() + tree.r[c]);
    }
    tree.x[n] = center.x();
    tree.y[n] = center.y();
    tree.z[n] = center.z();
    tree.r[n] = radius * (1 + 1e-12) + slack;
  }
  return tree;
}

std::size_t LeafCapacity(int levels, int branching) {
  std::size_t capacity = 1;
  for (int l = 1; l < levels; ++l) capacity *= static_cast<std::size_t>(branching);
  return capacity;
}

}  // namespace sulcus
