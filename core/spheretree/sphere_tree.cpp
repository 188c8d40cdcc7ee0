#include "core/spheretree/sphere_tree.h"

#include <cmath>

namespace sulcus {

std::size_t SphereTree::NumLeaves() const {
  std::size_t n = 0;
  for (std::uint8_t c : child_count) n += c == 0;
  return n;
}

std::vector<std::int32_t> SphereTree::NodesOnLevel(int l) const {
  std::vector<std::int32_t> out;
  for (std::size_t i = 0; i < size(); ++i) {
    if (level[i] == l) out.push_back(static_cast<std::int32_t>(i));
  }
  return out;
}

std::vector<std::int32_t> SphereTree::CutAtLevel(int l) const {
  std::vector<std::int32_t> out;
  for (std::size_t i = 0; i < size(); ++i) {
    if (level[i] == l || (level[i] < l && IsLeaf(i)))
      out.push_back(static_cast<std::int32_t>(i));
  }
  return out;
}

std::int32_t SphereTree::AddNode(const Vector3& c, double radius, int node_level) {
  x.push_back(c.x());
  y.push_back(c.y());
  z.push_back(c.z());
  r.push_back(radius);
  first_child.push_back(0);
  child_count.push_back(0);
  level.push_back(static_cast<std::uint8_t>(node_level));
  return static_cast<std::int32_t>(r.size() - 1);
}

void SphereTree::Validate() const {
  const std::size_t n = r.size();
  auto fail = [](const std::string& what) {
    throw std::runtime_error("invalid sphere-tree: " + what);
  };
  if (n == 0) fail("no nodes");
  if (x.size() != n || y.size() != n || z.size() != n || first_child.size() != n ||
      child_count.size() != n || level.size() != n) {
    fail("array sizes disagree");
  }
  if (levels < 1 || levels > 16)
    fail("levels " + std::to_string(levels) + " outside 1..16");
  if (branching < 2 || branching > 64)
    fail("branching " + std::to_string(branching) + " outside 2..64");
  if (level[0] != 0) fail("the root is not on level 0");
  std::vector<char> reached(n, 0);
  reached[0] = 1;
  for (std::size_t i = 0; i < n; ++i) {
    const std::string node = "node " + std::to_string(i);
    if (!std::isfinite(x[i]) || !std::isfinite(y[i]) || !std::isfinite(z[i]) ||
        !std::isfinite(r[i])) {
      fail(node + " has a non-finite value");
    }
    if (!(r[i] > 0))
      fail(node + " has radius " + std::to_string(r[i]) + ", expected > 0");
    if (level[i] >= levels)
      fail(node + " is on level " + std::to_string(level[i]) + " of " +
           std::to_string(levels));
    if (child_count[i] > branching)
      fail(node + " has more than " + std::to_string(branching) + " children");
    if (child_count[i] == 0) continue;
    const std::int64_t first = first_child[i], last = first + child_count[i];
    if (first <= static_cast<std::int64_t>(i) || last > static_cast<std::int64_t>(n)) {
      fail(node + " has children outside the node array");
    }
    for (std::int64_t c = first; c < last; ++c) {
      if (level[c] != level[i] + 1)
        fail("child " + std::to_string(c) + " of " + node + " is not one level deeper");
      if (reached[c]) fail("node " + std::to_string(c) + " has two parents");
      reached[c] = 1;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!reached[i]) fail("node " + std::to_string(i) + " is not reached from the root");
  }
}

}  // namespace sulcus
